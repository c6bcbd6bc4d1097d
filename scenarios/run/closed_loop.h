#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/grid.h"
#include "common/point_cloud.h"
#include "common/pose.h"
#include "common/stopwatch.h"
#include "controller/mpc_tracker.h"
#include "mapping/lidar_odometry.h"
#include "mapping/mover_tracker.h"
#include "mapping/traversability_mapper.h"
#include "planner/navigation/navigator.h"
#include "scenarios/run/lidar_pipeline.h"
#include "scenarios/run/mapping_pipeline.h"
#include "scenarios/run/run_metrics.h"
#include "scenarios/run/scenario.h"
#include "sim/actors/imu.h"
#include "sim/actors/pose_noise.h"
#include "sim/actors/social_force.h"
#include "sim/lidar/lidar_emulator.h"
#include "sim/lidar/ray_scene.h"
#include "sim/simulation.h"
#include "sim/terrain.h"

namespace trav::scenarios {

class ClosedLoop;

/// One physics step as observers and end conditions see it.
struct LoopStep {
  int index{0};                       ///< 0 for the first physics step
  common::RobotState state;           ///< the robot after the step (true state)
  common::RollPitchYaw rpy;           ///< of `state`
  common::Twist2 command;             ///< the body twist commanded during the step
  double vertical_acceleration_m_s2;  ///< of the base over the step, gravity removed
  bool last{false};                   ///< the scenario's duration ends with this step
};

/// Watches a run without changing it: recorders of files, metrics and video attach as observers.
/// Hooks are called in the order of a step, and observers in the order they were added.
class LoopObserver {
 public:
  virtual ~LoopObserver() = default;

  /// True if the observer needs each LiDAR frame's points placed in W (OnLidarFrame, OnMapInput).
  virtual bool WantsPoints() const { return false; }
  /// The world is set for the coming step (movers placed) and the command decided.
  virtual void OnCommand(const ClosedLoop& /*loop*/) {}
  /// A complete LiDAR frame; `points_W` are its points each placed with its own sensor pose
  /// (movers included; empty unless some observer or module wants points).
  virtual void OnLidarFrame(const ClosedLoop& /*loop*/, const lidar::LidarFrame& /*frame*/,
                            const Eigen::Matrix3Xf& /*points_W*/) {}
  /// What the mapper gets of a frame: points with movers removed and the base pose, both in the
  /// odometry frame O of the pose estimate (W itself when the pose is true), and the time.
  virtual void OnMapInput(const ClosedLoop& /*loop*/, const common::PointCloud& /*cloud_O*/,
                          const Eigen::Isometry3d& /*X_OB*/, double /*t_s*/) {}
  /// The mapper has produced a new map.
  virtual void OnMapUpdate(const ClosedLoop& /*loop*/) {}
  /// Before the physics step (the world as the step starts: video frames).
  virtual void BeforePhysics(const ClosedLoop& /*loop*/) {}
  /// After every physics step, before any end condition is checked.
  virtual void OnPhysicsStep(const ClosedLoop& /*loop*/, const LoopStep& /*step*/) {}
  /// After a physics step that no physical end condition (rollover, collision) ended, before the
  /// mission's end conditions (goal, stuck, planning failure, timeout).
  virtual void OnStepChecked(const ClosedLoop& /*loop*/, const LoopStep& /*step*/) {}
  /// Once, when the run has ended.
  virtual void OnEnd(const ClosedLoop& /*loop*/, Outcome /*outcome*/) {}
};

/// Decides whether a run ends after a physics step (Drake's monitor, one condition each).
class EndCondition {
 public:
  /// Physical conditions are checked before OnStepChecked observers, mission conditions after.
  enum class Stage { kPhysical, kMission };

  virtual ~EndCondition() = default;
  virtual Stage stage() const = 0;
  /// The outcome if the run ends with this step.
  virtual std::optional<Outcome> Check(const ClosedLoop& loop, const LoopStep& step) = 0;
};

/// A scenario's world as a run builds it first: the terrain and its obstacles (sim::GenerateTerrain
/// with the scenario's start and goal), the obstacles' height grid (sim::ObstacleHeightGrid) and
/// the ground truth (WorldGroundTruth). For a caller that built them already (trav eval's route
/// draw, RoutableWorld) to hand to the loop instead of their being built again.
struct PreparedWorld {
  sim::TerrainWorld world;
  Eigen::MatrixXf obstacle_heights;
  common::GridLayers truth_W;
};

/// Options of a loop that are not part of the scenario.
struct ClosedLoopOptions {
  std::string robot_model_path;  ///< the MJCF of the robot
  int max_lidar_frames{0};       ///< stop after this many frames (0: the scenario's duration)
  /// Map on a worker thread while the loop goes on, when the scenario's mapping latency is at
  /// least one physics step (MappingPipeline): the same run, bit for bit, in less wall time.
  bool mapping_thread{false};
  /// Cast each physics step's rays on a worker thread while the loop goes on (LidarPipeline): the
  /// same run, bit for bit, in less wall time.
  bool lidar_thread{false};
  /// The scenario's world built already, copied (it must be of the same scenario, start and
  /// goal: the same run, bit for bit); null: built here.
  const PreparedWorld* world{nullptr};
};

/// One run of a scenario as an object: the world (terrain, MuJoCo, movers, the LiDAR's ray scene)
/// and the robot's stack (drive script, MPC tracker or navigator; mapper; mover tracker; pose
/// noise), advanced physics step by physics step. Each step places the movers, decides the
/// command, scans, feeds the mapper the frames whose latency has passed, and steps the physics;
/// observers record and end conditions decide when the run ends. What it does is fixed by the
/// scenario and its seeds alone.
class ClosedLoop {
 public:
  /// Builds the world and the stack. @throws common::InputError on bad input (robot model, track
  /// reference file).
  ClosedLoop(const Scenario& scenario, const ClosedLoopOptions& options);
  ~ClosedLoop();
  ClosedLoop(const ClosedLoop&) = delete;
  ClosedLoop& operator=(const ClosedLoop&) = delete;

  /// Observers and end conditions, before Run. Observers are not owned.
  void AddObserver(LoopObserver* observer);
  void AddEndCondition(std::unique_ptr<EndCondition> condition);

  /// Runs until an end condition holds, the physics diverges, the frame limit is reached or the
  /// scenario's duration has passed; calls `progress` with the fraction simulated about every
  /// 0.5 s of simulation time and 1 at the end. Returns the outcome (kCompleted when nothing
  /// ended the run early).
  Outcome Run(const std::function<void(double fraction)>& progress = {});

  /// Wall time since construction began [s]: a run's wall time includes building its world.
  double wall_time_s() const { return wall_clock_.ElapsedSeconds(); }
  const Scenario& scenario() const { return scenario_; }
  const sim::TerrainWorld& world() const { return world_; }
  const sim::Simulation& simulation() const { return *simulation_; }
  /// For the renderer, which binds to the MuJoCo model (it does not change the run).
  sim::Simulation* mutable_simulation() { return simulation_.get(); }
  const std::vector<sim::MovingObstacle>& movers() const { return movers_; }
  /// The MuJoCo world's options (robot file, timestep, friction), for sim::ExportWorld.
  const sim::WorldOptions& world_options() const { return world_options_; }
  /// The world's obstacle heights (sim::ObstacleHeightGrid), computed once when first needed.
  const Eigen::MatrixXf& obstacle_heights() const;

  /// The LiDAR's mount X_BL: the scenario's `lidar.mount`, else the robot model's lidar site.
  Eigen::Isometry3d lidar_mount_B() const;

  /// X_OW: the odometry frame O of this step's pose estimate from W (identity for true poses).
  Eigen::Isometry3d OdometryFromWorld() const;

  /// The robot's true state at the start of the coming step, or after the last one.
  const common::RobotState& state() const { return state_; }
  /// The pose estimate the stack uses this step (its X_WB is the base in the odometry frame O).
  const common::RobotState& estimate() const { return estimate_; }
  const common::Twist2& command() const { return command_; }
  double timestep_s() const { return simulation_->timestep(); }
  int total_steps() const { return total_steps_; }
  int physics_steps() const { return physics_steps_; }

  /// The stack: the navigator (mode navigate), the MPC tracker (mode track), whether a mapper
  /// runs (not when nothing is mapped; the oracle maps nothing), the mover tracker (movers
  /// perceived from the scans).
  const planner::Navigator* navigator() const { return navigator_ ? &*navigator_ : nullptr; }
  const controller::TrajectoryTracker* tracker() const { return tracker_.get(); }
  bool has_mapper() const { return mapping_ != nullptr; }
  /// True when the mapper runs on a worker thread (ClosedLoopOptions::mapping_thread).
  bool mapping_threaded() const { return mapping_ && mapping_->threaded(); }
  /// True when the rays are cast on a worker thread (ClosedLoopOptions::lidar_thread).
  bool lidar_threaded() const { return lidar_ && lidar_->threaded(); }
  /// The mapper's latest map in effect (MappingPipeline); null before the first or without one.
  const common::GridLayers* map() const { return mapping_ ? mapping_->map() : nullptr; }
  bool perceives_movers() const { return mover_tracker_.has_value(); }
  /// The map the navigator plans on (the mapper's, or the truth for the oracle; null before the
  /// first map).
  const common::GridLayers* navigation_map() const { return navigation_map_; }
  /// The ground truth of the whole world (mode navigate).
  const common::GridLayers* truth() const { return truth_W_ ? &*truth_W_ : nullptr; }
  /// The movers as discs at their true state, and as the navigator predicts them, this step.
  const std::vector<planner::MovingObstacle>& true_movers() const { return true_movers_; }
  const std::vector<planner::MovingObstacle>& predicted_movers() const { return predicted_movers_; }
  /// The navigator's tick of this step (mode navigate).
  const planner::NavigatorTick& navigator_tick() const { return navigator_tick_; }

  /// LiDAR frames so far, their points and the time spent casting them.
  int lidar_frames() const { return lidar_frames_; }
  double lidar_points() const { return lidar_points_; }
  double lidar_cast_s() const { return lidar_cast_s_; }
  /// Every map update: its result and wall time [ms].
  const std::vector<mapping::MapUpdateResult>& map_updates() const { return map_updates_; }
  /// The IMU (its samples of the last physics step), or nullptr when `imu.enabled` is false or
  /// the robot model has no IMU.
  const sim::Imu* imu() const { return imu_ ? &*imu_ : nullptr; }
  const std::vector<double>& mapping_ms() const { return mapping_ms_; }
  /// Mean error of the latest map against the truth (NaN before the first; mode navigate).
  double last_mapping_error() const { return last_mapping_error_; }

  /// Wall time per module ("lidar", "mapping", "planning", "control", "physics", "render"), for
  /// the summary and the time series; observers add their own (render).
  ModuleTimes& times() { return times_; }
  const ModuleTimes& times() const { return times_; }

 private:
  void PlaceMovers();
  void DecideCommand();
  // false when the frame limit is reached
  bool Scan();
  void MapPendingFrames();
  // This step's pose estimate: the pose noise model's, or with scan-matching the pose of the last
  // registered scan carried on by the motion since.
  common::RobotState EstimatePose();
  // Adds the wall times of the steps scanned since the last call to the "lidar" module's.
  void TakeScanTimes();
  // Registers a complete frame with the LiDAR odometry (scan-matching).
  void RegisterScan();
  std::optional<Outcome> CheckEnd(EndCondition::Stage stage, const LoopStep& step);

  const common::Stopwatch wall_clock_;
  const Scenario scenario_;
  const sim::TerrainWorld world_;
  mutable std::optional<Eigen::MatrixXf> obstacle_heights_;
  std::unique_ptr<controller::TrajectoryTracker> tracker_;
  std::vector<sim::MovingObstacle> movers_;
  const sim::WorldOptions world_options_;
  std::unique_ptr<sim::Simulation> simulation_;
  sim::SocialForceCrowd crowd_;
  std::unique_ptr<LidarPipeline> lidar_;
  lidar::LidarFrame lidar_frame_;
  std::optional<Eigen::Isometry3d> X_BL_;  // the scenario's mount; else the model's lidar site
  std::unique_ptr<MappingPipeline> mapping_;
  std::optional<common::GridLayers> truth_W_;
  std::optional<planner::Navigator> navigator_;
  std::optional<sim::PoseNoise> pose_noise_;
  // localization method scan-matching: the odometry, the sensor in the base frame, and the pose
  // of the base at the last registered scan in O and (to carry it on between scans) in W
  std::unique_ptr<mapping::LidarOdometry> odometry_;
  Eigen::Isometry3d X_BL_odometry_{Eigen::Isometry3d::Identity()};
  struct ScanPose {
    Eigen::Isometry3d X_OB;
    Eigen::Isometry3d X_WB;
  };
  std::optional<ScanPose> last_scan_pose_;
  // the gyroscope's rotation of the base since the last registered scan (the IMU's axes are the
  // base's), the odometry's rotation prior
  Eigen::Matrix3d gyro_turn_B_{Eigen::Matrix3d::Identity()};
  std::optional<sim::Imu> imu_;
  std::optional<mapping::MoverTracker> mover_tracker_;

  std::vector<LoopObserver*> observers_;
  std::vector<std::unique_ptr<EndCondition>> end_conditions_;
  bool observers_want_points_{false};
  int max_lidar_frames_{0};

  common::RobotState state_;
  common::RobotState estimate_;  // the stack's belief of state_: X_WB is X_OB
  common::Twist2 command_;
  planner::NavigatorTick navigator_tick_;
  std::vector<planner::MovingObstacle> true_movers_;
  std::vector<planner::MovingObstacle> predicted_movers_;
  const common::GridLayers* navigation_map_{nullptr};
  bool map_changed_{false};
  int total_steps_{0};
  int physics_steps_{0};
  double previous_vertical_speed_m_s_{0.0};
  int lidar_frames_{0};
  double lidar_points_{0.0};
  double lidar_cast_s_{0.0};
  std::vector<double> scan_ms_;  // the steps' scan times handed over last
  std::vector<mapping::MapUpdateResult> map_updates_;
  std::vector<double> mapping_ms_;
  double last_mapping_error_;
  ModuleTimes times_;
};

}  // namespace trav::scenarios
