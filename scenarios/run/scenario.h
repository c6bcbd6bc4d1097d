#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/archive.h"
#include "common/enum_names.h"
#include "common/pose.h"
#include "common/yaml_reader.h"
#include "controller/mpc.h"
#include "controller/skid_steer.h"
#include "mapping/fsgp_config.h"
#include "mapping/ground_truth.h"
#include "mapping/lidar_odometry.h"
#include "planner/navigation/navigator.h"
#include "planner/navigation_planner.h"
#include "renders/camera.h"
#include "renders/renderer.h"
#include "scenarios/run/track_reference.h"
#include "sim/actors/imu.h"
#include "sim/actors/pose_noise.h"
#include "sim/actors/traffic.h"
#include "sim/lidar/lidar_config.h"
#include "sim/moving_obstacles.h"
#include "sim/terrain.h"

namespace trav::scenarios {

/// How a run ended.
enum class Outcome {
  kCompleted,   ///< ran for the whole duration (modes drive and track)
  kSuccess,     ///< reached the goal (mode navigate)
  kCollision,   ///< the robot touched an obstacle or a mover (wheels on the ground do not count)
  kRolledOver,  ///< the robot tilted beyond the rollover limit
  kStuck,       ///< no progress toward the goal for `navigation.stuck_time`
  kTimeout,     ///< the duration ran out before the goal (mode navigate)
  kPlanningFailure,  ///< no valid plan for `navigation.planning_failure_time`
  kDiverged,         ///< the physics produced a bad state
};

/// The names of Outcome's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<Outcome>, 8> kOutcomeNames{
    {{Outcome::kCompleted, "completed"},
     {Outcome::kSuccess, "success"},
     {Outcome::kCollision, "collision"},
     {Outcome::kRolledOver, "rolled_over"},
     {Outcome::kStuck, "stuck"},
     {Outcome::kTimeout, "timeout"},
     {Outcome::kPlanningFailure, "planning_failure"},
     {Outcome::kDiverged, "diverged"}}};
constexpr const auto& EnumNames(Outcome) { return kOutcomeNames; }

/// Which traversability mapper runs on the LiDAR frames (scenario key `mapping.method`);
/// kGroundTruth is the oracle: the ground-truth map of the whole world, no LiDAR needed.
enum class MapperMethod { kFsgpBgk, kFsgp, kFsgpAccumulation, kSgp, kElevationMap, kGroundTruth };

/// The names of MapperMethod's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<MapperMethod>, 6> kMapperMethodNames{
    {{MapperMethod::kFsgpBgk, "fsgp-bgk"},
     {MapperMethod::kFsgp, "fsgp"},
     {MapperMethod::kFsgpAccumulation, "fsgp-accumulation"},
     {MapperMethod::kSgp, "sgp"},
     {MapperMethod::kElevationMap, "em"},
     {MapperMethod::kGroundTruth, "ground-truth"}}};
constexpr const auto& EnumNames(MapperMethod) { return kMapperMethodNames; }

/// A failure `trav run` fakes on purpose (scenario key test_fault).
enum class TestFault { kNone, kCrash, kHang };

/// The names of TestFault's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<TestFault>, 3> kTestFaultNames{
    {{TestFault::kNone, "none"}, {TestFault::kCrash, "crash"}, {TestFault::kHang, "hang"}}};
constexpr const auto& EnumNames(TestFault) { return kTestFaultNames; }

/// What drives the robot.
enum class RunMode {
  kDrive,     ///< the open-loop `drive` script
  kTrack,     ///< the MPC tracking the `track` reference (no mapping or planning)
  kNavigate,  ///< the closed loop: map from scans, plan to the goal, track the plan
};

/// The names of RunMode's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<RunMode>, 3> kRunModeNames{
    {{RunMode::kDrive, "drive"}, {RunMode::kTrack, "track"}, {RunMode::kNavigate, "navigate"}}};
constexpr const auto& EnumNames(RunMode) { return kRunModeNames; }

/// One segment of an open-loop drive script: a constant body twist held for a duration.
struct DriveSegment {
  double v_m_s{0.0};        ///< forward speed [m/s]
  double omega_rad_s{0.0};  ///< yaw rate [rad/s]
  double duration_s{1.0};   ///< [s], > 0
  /// The keys of an item of scenario section `drive` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("v", &v_m_s, {-30, 30});
    a->Field("omega", &omega_rad_s, {-30, 30});
    a->Field("duration", &duration_s, {0.001, 86400.0});
  }
};

/// Video settings of a run (docs/video.md).
struct VideoSettings {
  VideoSettings() {
    render.width = 1280;
    render.height = 720;
  }
  bool enabled{true};
  renders::RenderConfig render{};  ///< the frame: 1280 x 720 by default, the map panel included
  double fps{30.0};                ///< frames per second of simulation time, in (0, 120]
  renders::CameraMode camera{renders::CameraMode::kChase};
  renders::CameraView camera_pose{};  ///< the camera `fixed`'s pose
  double orbit_period_s{24.0};        ///< one turn of the camera `orbit` [s]
  double top_down_span_m{14.0};       ///< what the camera `top_down` shows top to bottom [m]
  int lidar_frames{3};                ///< LiDAR frames drawn, the older fading out
  bool map_overlay{true};             ///< the robot's map draped on the ground
  int crf{20};                        ///< H.264 quality: x264's constant rate factor, 0..51
  double end_card_s{2.0};             ///< the end card's time in a closed loop's video [s]
  /// The keys of scenario section `video` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("enabled", &enabled);
    a->Field("fps", &fps, {1.0, 120.0});
    a->Enum("camera", &camera);
    a->Map("camera_pose", &camera_pose);
    a->Field("orbit_period", &orbit_period_s, {1.0, 3600.0});
    a->Field("top_down_span", &top_down_span_m, {1.0, 1000.0});
    a->Field("lidar_frames", &lidar_frames, {0, 50});
    a->Field("map_overlay", &map_overlay);
    a->Field("crf", &crf, {0, 51});
    a->Field("end_card", &end_card_s, {0.0, 60.0});
    render.Serialize(a);
  }
};

/// A scenario file, schema version 1 (docs/scenario-format.md lists every key).
struct Scenario {
  std::string name{"default"};
  sim::TerrainConfig terrain{};
  std::string robot_model{"scout_mini.xml"};  ///< file in the models folder, or an absolute path
  common::Pose2 start_W{};                    ///< robot.start: [x, y, yaw] [m, m, rad]
  Eigen::Vector2d goal_W{10.0, 0.0};          ///< [m]; kept clear of obstacles
  controller::SkidSteerConfig skid_steer{};   ///< robot.skid_steer
  double physics_timestep_s{0.002};           ///< [s], in (0, 0.01]
  double ground_friction{0.9};                ///< in (0, 5]
  double duration_s{30.0};                    ///< [s], > 0
  RunMode mode{RunMode::kDrive};
  std::vector<DriveSegment> drive;  ///< open-loop script; zero twist after its end
  TrackSettings track{};            ///< the reference of mode `track`
  /// controller.mpc (its control period is 1 / controller.rate, 50 Hz by default)
  controller::MpcConfig mpc{};
  planner::NavigationPlannerConfig planner{};  ///< scenario key `planner` (mode navigate)
  /// planner.method: the path search, `astar` or OMPL's `rrt_star`, `bit_star`, `rrt_connect`, or
  /// a registered one (scenarios/run/plugins.h)
  std::string planner_method{"astar"};
  /// controller.method: what tracks the trajectories, `mpc` or a registered controller
  /// (scenarios/run/plugins.h)
  std::string controller_method{"mpc"};
  /// planner.sampling_iterations: the iterations of one OMPL query (its only budget: repeatable)
  int sampling_iterations{1000};
  planner::NavigationSettings navigation{};  ///< scenario key `navigation` (mode navigate)
  /// navigation.position_noise, yaw_noise, drift, localization_seed: the pose the stack believes
  sim::PoseNoiseConfig pose_noise{};
  /// localization's scan-matching keys: the LiDAR odometry of method scan-matching
  mapping::LidarOdometryConfig lidar_odometry{};
  double rollover_limit_deg{60.0};  ///< tilt that ends the run as rolled over [deg]
  /// moving_obstacles: movers of the closed loop (MuJoCo mocap bodies the LiDAR sees)
  std::vector<sim::MovingObstacle> movers;
  /// traffic: movers generated from a count, speed and seed for the route and the world
  /// (ScenarioMovers), after `movers`.
  sim::TrafficSettings traffic{};
  lidar::LidarConfig lidar{};
  /// lidar.mount: pose of the sensor L in the base frame B as [x, y, z, roll, pitch, yaw]
  /// [m, rad]; absent: the robot model's "lidar" site.
  std::optional<Eigen::Matrix<double, 6, 1>> lidar_mount_B;
  sim::ImuConfig imu{};        ///< imu: the IMU written to imu.csv
  bool mapping_enabled{true};  ///< mapping.enabled: map every LiDAR frame
  /// mapping.method: a built-in (MapperMethod's names) or a registered mapper
  /// (scenarios/run/plugins.h)
  std::string mapper{"fsgp-bgk"};
  mapping::FsgpConfig mapping{};              ///< the other keys of `mapping`
  mapping::GroundTruthConfig ground_truth{};  ///< scenario key `ground_truth`
  VideoSettings video{};
  std::string output_dir{"out/default"};
  bool mcap{false};  ///< output.mcap: write run.mcap (scenarios/run/mcap_recorder.h)
  /// output.mcap_map_period: simulation time between two maps in run.mcap [s] (0: every update)
  double mcap_map_period_s{0.5};
  /// Exit code 0 iff the run ends this way; default: success in mode navigate, else completed.
  Outcome expected_outcome{Outcome::kCompleted};
  /// test_fault: makes `trav run` crash (abort) or hang instead of running, to test what runs
  /// many scenarios (`trav batch`) against failing runs.
  TestFault test_fault{TestFault::kNone};
};

/// True if the scenario's robot plans on the ground truth itself (`mapping.method: ground-truth`,
/// the oracle): no mapper runs.
inline bool UsesGroundTruthMap(const Scenario& scenario) {
  return scenario.mapper == common::NameOf(MapperMethod::kGroundTruth);
}

/// Loads a scenario strictly: unknown keys, wrong types and out-of-range values throw
/// common::InputError naming the source, the key path and the value.
Scenario LoadScenario(const common::YamlDocument& document);

/// Applies `--set` overrides ("key.path=value", the value in YAML) to `document` in order.
/// @throws common::InputError naming --set and the assignment if one has no '=' or no key.
void ApplyOverrides(const std::vector<std::string>& assignments, common::YamlDocument* document);

/// The YAML text of the built-in default scenario (the closed loop across 30 m of forest, with
/// video).
const std::string& DefaultScenarioYaml();

/// The scenario as YAML text, every field resolved (written next to a run's outputs so it can be
/// replayed).
std::string ResolvedScenarioYaml(const Scenario& scenario);

/// The bounds of every numeric scenario key, as a Markdown table ("| `key.path` | min | max |"),
/// sorted by key; "[i]" stands for any item of a sequence. docs/scenario-format.md holds it.
std::string ScenarioBoundsTable();

/// Every key path a scenario file can hold, sorted ("terrain.parameters.octaves",
/// "moving_obstacles[i].speed"; "[i]" stands for any item of a sequence). A test checks that
/// docs/scenario-format.md (and docs/terrains.md for terrain parameters) names each.
std::vector<std::string> ScenarioKeys();

/// The pose X_BL of a mount given as [x, y, z, roll, pitch, yaw].
Eigen::Isometry3d MountPose(const Eigen::Matrix<double, 6, 1>& mount);

/// The drive command at time t: the segment covering t, or zero after the script ends.
common::Twist2 DriveCommandAt(const std::vector<DriveSegment>& drive, double t_s);

}  // namespace trav::scenarios
