#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "common/grid.h"
#include "common/point_cloud.h"
#include "common/pose.h"
#include "scenarios/run/closed_loop.h"
#include "scenarios/run/end_conditions.h"
#include "scenarios/run/run_metrics.h"
#include "scenarios/run/scenario.h"
#include "sim/terrain.h"
#include "sim/terrain_geometry.h"

namespace trav::scenarios {

/// What the closed loop (mode navigate) reports.
struct NavigationMetrics {
  bool goal_reached{false};
  double time_to_goal_s{0.0};         ///< simulation time at success (0 otherwise)
  double final_goal_distance_m{0.0};  ///< distance from the base to the goal at the end
  double optimal_path_length_m{0.0};  ///< A* on the ground-truth map, simplified (0: no path)
  double path_length_ratio{0.0};      ///< driven distance / optimal path length
  double barn_score{0.0};             ///< BARN score with OT = optimal length / max speed
  double rms_vertical_acceleration_m_s2{0.0};  ///< of the base, gravity removed
  int plans{0};
  int failed_plans{0};
  int replans_on_events{0};
  int safety_stops{0};
  int give_ways{0};    ///< times the stopped robot drove out of a mover's way
  int back_offs{0};    ///< times the stalled robot backed off for a run-up
  int step_climbs{0};  ///< times the robot began to climb a step straight (Navigator)
  /// Plans that fell back on a manoeuvre, by planner::Fallback (docs/navigation.md).
  std::array<int, planner::kFallbackNames.size()> fallbacks{};
  std::string last_planner_status;
  /// Why a planning failure ended the run: "no_plan" or "livelock" (PlanningFailureCondition);
  /// empty for every other outcome.
  std::string planning_failure_cause;
  /// Movers perceived from the scans (navigation.movers_from_ground_truth false), sampled every
  /// physics step: the mean distance from each perceived mover to the nearest true one over those
  /// within kFalseMoverDistance_m (scenarios/run/recorders.h) of one [m], how many such samples
  /// there were, and how many perceived movers had no true one that close (false movers).
  double mover_tracking_error_m{0.0};
  int perceived_mover_samples{0};
  int false_mover_samples{0};
  /// Smallest gap between the robot's disc and a mover's footprint (infinite: no movers) [m].
  double min_mover_clearance_m{std::numeric_limits<double>::infinity()};
  /// Times a mover came closer than navigation.near_miss_clearance without a collision (each
  /// approach counts once; it counts again after the gap has reopened by 0.1 m).
  int near_misses{0};
  Eigen::Vector2d goal_W{Eigen::Vector2d::Zero()};  ///< the scenario's goal
  double path_length_m{0.0};                        ///< the distance driven (RunSummary)
};

/// summary.json's "navigation" object (min_mover_clearance_m null when infinite).
void to_json(nlohmann::json& json, const NavigationMetrics& metrics);

/// Mapping on the LiDAR frames (when both are enabled): updates, time per update, and the final
/// map's error against the ground truth over its known cells.
struct MappingMetrics {
  std::string method{"fsgp-bgk"};  ///< `mapping.method`
  int updates{0};
  double update_ms_median{0.0};
  double update_ms_max{0.0};
  /// Median time per mapper stage [ms] by name (crop, features, fit, predict, fusion, smoothing).
  std::map<std::string, double> stage_ms_median;
  int training_points_median{0};  ///< median training points per update
  int known_cells{0};
  double mean_error{0.0};      ///< mean |traversability - ground truth|
  double error_variance{0.0};  ///< variance of |traversability - ground truth|
};

/// summary.json's "mapping" object.
void to_json(nlohmann::json& json, const MappingMetrics& metrics);

/// How far the stack's pose estimate was from the truth (when localisation is not the true pose).
struct LocalizationMetrics {
  sim::LocalizationMethod method{sim::LocalizationMethod::kTrue};
  double final_position_error_m{0.0};  ///< horizontal, at the end of the run
  double final_z_error_m{0.0};
  double final_yaw_error_deg{0.0};
  double max_position_error_m{0.0};  ///< horizontal, over the run
  /// The relative pose error over 10 m, odometry's usual drift metric: over every stretch of 10 m
  /// driven (starting every 0.1 m), the difference between the estimated and the true motion
  /// across it; means of its length [m] and of its yaw [deg], and the number of stretches (0, and
  /// the means 0, when the robot drove less than 10 m).
  double relative_error_10m_m{0.0};
  double relative_yaw_error_10m_deg{0.0};
  int relative_error_stretches{0};
};

/// summary.json's "localization" object.
void to_json(nlohmann::json& json, const LocalizationMetrics& metrics);

/// What `trav run` reports in summary.json.
struct RunSummary {
  Outcome outcome{Outcome::kCompleted};
  double sim_time_s{0.0};
  double wall_time_s{0.0};
  double real_time_factor{0.0};  ///< simulated seconds per wall-clock second
  double distance_m{0.0};        ///< horizontal path length of the base
  double max_roll_deg{0.0};      ///< largest |roll|
  double max_pitch_deg{0.0};     ///< largest |pitch|
  double rms_roll_deg{0.0};
  double rms_pitch_deg{0.0};
  common::Pose2 final_pose_W{};
  int physics_steps{0};
  int mujoco_warning_count{0};
  std::vector<std::string> mujoco_warnings;
  int video_frames{0};                 ///< 0 when video is off
  bool mcap{false};                    ///< run.mcap was written
  int lidar_frames{0};                 ///< complete LiDAR frames (0 when the LiDAR is off)
  double lidar_points_per_frame{0.0};  ///< mean points per frame
  double lidar_ms_per_frame{0.0};      ///< mean wall time spent casting one frame's rays [ms]
  std::optional<controller::TrackingMetrics> tracking;  ///< modes track and navigate
  std::optional<MappingMetrics> mapping;                ///< when a mapper updated its map
  std::optional<NavigationMetrics> navigation;          ///< mode navigate only
  std::optional<CollisionRecord> collision;             ///< outcome collision only
  std::optional<LocalizationMetrics> localization;      ///< when the pose is estimated
  std::map<std::string, ModuleTime> compute;            ///< wall time per module
  /// Mode navigate: the PNG plots written (speed, roll and pitch, mapping error, compute), or null
  /// when gnuplot is missing.
  nlohmann::json plots;
};

/// summary.json's keys of a run (all but those of its scenario): the optional sections when
/// present, "plots" with "navigation".
void to_json(nlohmann::json& json, const RunSummary& summary);

/// summary.json: the scenario a run ran and the run's summary.
struct SummaryFile {
  std::string scenario;  ///< the scenario's name
  Outcome expected_outcome{Outcome::kCompleted};
  sim::TerrainType terrain_type{sim::TerrainType::kHilly};
  std::uint64_t terrain_seed{1};
  nlohmann::json provenance;  ///< Provenance of the resolved scenario
  RunSummary summary;
};

/// summary.json's object.
void to_json(nlohmann::json& json, const SummaryFile& file);

/// A summary.json of default values with every section a run can report (tracking, mapping,
/// navigation with a finite mover clearance, collision, the time of every module in
/// kTimedModules): its numbers are every metric summary.json can have.
SummaryFile SummaryWithEverySection();

/// Options of a run that are not part of the scenario.
struct RunOptions {
  bool record_clouds{false};   ///< write every LiDAR frame as clouds/frame_NNNNNN.pcd
  int max_lidar_frames{0};     ///< stop after this many frames (0: run the scenario's duration)
  bool mapping_thread{false};  ///< ClosedLoopOptions::mapping_thread
  bool lidar_thread{false};    ///< ClosedLoopOptions::lidar_thread
};

/// Progress reports: fraction of the scenario's duration simulated so far, in [0, 1].
using ProgressCallback = std::function<void(double fraction)>;

/// Runs `loop` to its end under the scenario's end conditions (rollover and collision always; in
/// mode navigate goal, stuck, planning failure and timeout) with `observers` attached after the
/// run's own statistics, and returns its summary (writing no file). `video_frames` and `plots`
/// are left for the caller; `final_map_truth`, when given, receives the ground truth on the
/// final map's cells (when a mapper ran).
RunSummary RunLoop(ClosedLoop* loop, const std::vector<LoopObserver*>& observers,
                   const ProgressCallback& progress = {},
                   std::optional<common::GridLayers>* final_map_truth = nullptr);

/// Runs a scenario: generates its terrain, builds the MuJoCo world, drives the robot (mode drive:
/// by the scenario's script; mode track: by the MPC tracking the reference, which starts at the
/// robot's start pose or, for a file, places the robot at its first point) through the skid-steer
/// mapping while the LiDAR scans (each physics step
/// casts the rays of that step from the sensor pose of that step), and writes into `output_dir`
/// (which must exist) `trajectory.csv` (50 Hz), with video on `video.mp4` (the latest LiDAR frame's
/// points drawn coloured by height) and with `options.record_clouds` the frames as PCD under
/// `clouds/`. Stops early on rollover or divergence (recorded as the outcome).
/// @throws common::InputError on bad input (an unreadable robot model); std::runtime_error if
/// video was asked for and GL or ffmpeg is missing.
RunSummary RunScenario(const Scenario& scenario, const std::string& robot_model_path,
                       const std::string& output_dir, const RunOptions& options = {},
                       const ProgressCallback& progress = {});

/// The ground-truth traversability of the whole world at the scenario's mapping resolution, from
/// the world's obstacle heights (sim::ObstacleHeightGrid).
common::GridLayers WorldGroundTruth(const Scenario& scenario, const sim::TerrainWorld& world,
                                    const Eigen::MatrixXf& obstacle_heights);

/// The obstacles of `world` as the physical ground truth rests the robot on them: the material
/// within the Scout Mini's height above the ground, outlined every
/// mapping::kObstacleOutlineResolution_m (sim::ObstacleBandRaster).
sim::ObstacleRaster RestingObstacles(const sim::TerrainWorld& world);

/// The physical ground truth (mapping::ComputePhysicalTruth, docs/ground-truth.md) of `world` on
/// `map_geometry`: the Scout Mini resting on its ground and RestingObstacles. With `cells` only at
/// those cells (ix, iy), NaN elsewhere.
common::GridLayers WorldPhysicalTruth(const common::GridGeometry& map_geometry,
                                      const sim::TerrainWorld& world,
                                      const mapping::GroundTruthConfig& config,
                                      const std::vector<Eigen::Vector2i>* cells = nullptr);

/// The ground truth of the scenario's world, generated from its terrain for its start and goal.
common::GridLayers ScenarioGroundTruth(const Scenario& scenario);

/// Length of the simplified A* path (the scenario's search settings) from the scenario's start to
/// its goal on the ground truth `truth_W` [m]; 0 if there is none.
double OptimalPathLength(const Scenario& scenario, const common::GridLayers& truth_W);

/// The scenario's world with its ground truth (what its closed loop builds first) if A* finds a
/// path from its start to its goal on the truth, else nothing. A route is first tried on the
/// world's obstacles alone (cells with an obstacle higher than the ground truth's clearance,
/// milliseconds), so that a blocked route is rejected before the truth is computed (seconds).
std::optional<PreparedWorld> RoutableWorld(const Scenario& scenario);

/// The moving obstacles of a run: the scenario's `moving_obstacles`, then its `traffic` spawned for
/// its route clear of the world's static obstacles (`obstacle_heights`, sim::ObstacleHeightGrid;
/// sim::SpawnTraffic).
std::vector<sim::MovingObstacle> ScenarioMovers(const Scenario& scenario,
                                                const sim::TerrainWorld& world,
                                                const Eigen::MatrixXf& obstacle_heights);

/// Absolute path of the robot model of `scenario` (robot.model in `models_dir` unless absolute).
std::string RobotModelPath(const Scenario& scenario, const std::string& models_dir);

/// The robot file `robot_model_path` as a URDF for ROS tools (sim::RobotUrdf).
/// @throws common::InputError naming the file if it does not load or URDF cannot say it.
std::string RobotUrdfOf(const std::string& robot_model_path);

/// RobotModelPath, checked to be a robot model trav can drive (sim::ValidateRobotModel).
/// @throws common::InputError if it is not.
std::string CheckedRobotModelPath(const Scenario& scenario, const std::string& models_dir);

/// summary.json's "collision" object.
void to_json(nlohmann::json& json, const CollisionRecord& record);

/// summary.json text of a run.
std::string SummaryJson(const Scenario& scenario, const RunSummary& summary);

}  // namespace trav::scenarios

namespace trav::controller {

/// summary.json's "tracking" object.
void to_json(nlohmann::json& json, const TrackingMetrics& metrics);

}  // namespace trav::controller
