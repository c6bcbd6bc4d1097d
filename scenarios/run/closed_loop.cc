#include "scenarios/run/closed_loop.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "common/stopwatch.h"
#include "controller/skid_steer.h"
#include "mapping/ground_truth.h"
#include "scenarios/run/mappers.h"
#include "scenarios/run/plugins.h"
#include "scenarios/run/scenario_run.h"
#include "scenarios/run/track_reference.h"
#include "sim/terrain_geometry.h"

namespace trav::scenarios {
namespace {

// Every mover as a disc at constant velocity from its true state at t.
std::vector<planner::MovingObstacle> TrueMovers(const std::vector<sim::MovingObstacle>& all,
                                                const sim::Simulation& simulation, double t_s) {
  std::vector<planner::MovingObstacle> movers;
  for (int i = 0; i < simulation.num_movers(); ++i) {
    planner::MovingObstacle mover;
    mover.position_W = simulation.MoverPose(i).translation().head<2>();
    mover.velocity_W = simulation.MoverVelocity(i);
    mover.radius_m = sim::MoverFootprintRadius(all[static_cast<std::size_t>(i)]);
    mover.t_s = t_s;
    movers.push_back(mover);
  }
  return movers;
}

// The movers the planner perceives: the tracker's moving tracks, at constant velocity from their
// last update.
std::vector<planner::MovingObstacle> PerceivedMovers(const mapping::MoverTracker& tracker) {
  std::vector<planner::MovingObstacle> movers;
  for (const mapping::TrackedMover& track : tracker.Movers()) {
    movers.push_back({track.position_W, track.velocity_W, track.radius_m, track.t_s});
  }
  return movers;
}

// A disc in the odometry frame O: where a mover stands.
struct Disc {
  Eigen::Vector2d centre_O;
  double radius_m;
};

// The movers' footprints from their true poses, placed in O by X_OW.
std::vector<Disc> TrueMoverDiscs(const std::vector<sim::MovingObstacle>& movers,
                                 const sim::Simulation& simulation, const Eigen::Isometry3d& X_OW) {
  std::vector<Disc> discs;
  for (int k = 0; k < simulation.num_movers(); ++k) {
    discs.push_back({(X_OW * simulation.MoverPose(k).translation()).head<2>(),
                     sim::MoverFootprintRadius(movers[static_cast<std::size_t>(k)])});
  }
  return discs;
}

// The footprints of the movers the tracker perceives at t.
std::vector<Disc> PerceivedMoverDiscs(const mapping::MoverTracker& tracker, double t_s) {
  std::vector<Disc> discs;
  for (const mapping::TrackedMover& track : tracker.Movers()) {
    discs.push_back({track.position_W + (t_s - track.t_s) * track.velocity_W, track.radius_m});
  }
  return discs;
}

// Drops the points within a margin of the discs before mapping: a mover mapped as terrain leaves
// a trail of ghost obstacles (what the mapper misses is cleared when the cells are seen free
// again).
void RemovePointsInDiscs(const std::vector<Disc>& discs, common::PointCloud* cloud_O) {
  constexpr double kMargin_m = 0.3;
  if (discs.empty()) return;
  Eigen::Index kept = 0;
  for (Eigen::Index i = 0; i < cloud_O->size(); ++i) {
    const Eigen::Vector2d p = cloud_O->points.col(i).head<2>().cast<double>();
    const bool on_mover = std::any_of(discs.begin(), discs.end(), [&](const Disc& disc) {
      const double reach = disc.radius_m + kMargin_m;
      return (p - disc.centre_O).squaredNorm() < reach * reach;
    });
    if (!on_mover) cloud_O->points.col(kept++) = cloud_O->points.col(i);
  }
  cloud_O->points.conservativeResize(3, kept);
  cloud_O->time_offsets.resize(0);
  cloud_O->line_ids.resize(0);
}

// The robot's start: the scenario's, or the first point of the reference it tracks.
common::Pose2 StartPose(const Scenario& scenario, const controller::TrajectoryTracker* tracker) {
  common::Pose2 start_W = scenario.start_W;
  if (tracker != nullptr) {
    const common::TrajectoryPoint first =
        tracker->reference().Sample(tracker->reference().start_time());
    start_W.position = first.position_W;
    start_W.yaw = first.yaw;
  }
  return start_W;
}

// What drives the robot in mode track: the controller of `controller.method` (the MPC by default)
// tracking the scenario's reference.
std::unique_ptr<controller::TrajectoryTracker> MakeTracker(const Scenario& scenario) {
  if (scenario.mode != RunMode::kTrack) return nullptr;
  std::unique_ptr<controller::TrajectoryTracker> tracker =
      FindController(scenario.controller_method)(scenario);
  tracker->SetReference(BuildReference(scenario.track, scenario.start_W));
  return tracker;
}

sim::WorldOptions WorldOptionsOf(const Scenario& scenario, const ClosedLoopOptions& options) {
  sim::WorldOptions world_options;
  world_options.robot_model_path = options.robot_model_path;
  world_options.timestep_s = scenario.physics_timestep_s;
  world_options.ground_friction = scenario.ground_friction;
  return world_options;
}

}  // namespace

ClosedLoop::ClosedLoop(const Scenario& scenario, const ClosedLoopOptions& options)
    : wall_clock_(),
      scenario_(scenario),
      world_(options.world != nullptr
                 ? options.world->world
                 : sim::GenerateTerrain(scenario.terrain,
                                        {scenario.start_W.position, scenario.goal_W})),
      obstacle_heights_(options.world != nullptr
                            ? std::optional<Eigen::MatrixXf>(options.world->obstacle_heights)
                            : std::nullopt),
      tracker_(MakeTracker(scenario)),
      movers_(scenario.traffic.count > 0 ? ScenarioMovers(scenario, world_, obstacle_heights())
                                         : scenario.movers),
      world_options_(WorldOptionsOf(scenario, options)),
      simulation_(std::make_unique<sim::Simulation>(world_, StartPose(scenario, tracker()),
                                                    world_options_, movers_)),
      crowd_(movers_),
      max_lidar_frames_(options.max_lidar_frames),
      last_mapping_error_(std::nan("")) {
  // LiDAR: an Embree scene of the same world, scanned every physics step
  if (scenario.lidar_mount_B) X_BL_ = MountPose(*scenario.lidar_mount_B);
  if (scenario.lidar.enabled) {
    lidar_ = std::make_unique<LidarPipeline>(
        std::make_unique<lidar::RayScene>(sim::RaySceneOf(world_, movers_)),
        std::make_unique<lidar::LidarEmulator>(scenario.lidar), options.lidar_thread);
  }
  // mapping: every LiDAR frame, in W with each point's own sensor pose
  const bool oracle = UsesGroundTruthMap(scenario);
  if (lidar_ && scenario.mapping_enabled && !oracle) {
    // a worker overlaps nothing unless a frame's map takes effect a step or more after its scan
    const bool worker = options.mapping_thread &&
                        scenario.navigation.mapping_latency_s >= simulation_->timestep() - 1e-12;
    std::unique_ptr<mapping::TraversabilityMapper> mapper = MakeMapper(scenario);
    // the worker's mapper may use a helper thread of its own, for a core the loop leaves free
    if (worker) mapper->UseHelperThread();
    mapping_ = std::make_unique<MappingPipeline>(std::move(mapper), worker);
  }

  // the closed loop: the ground truth for the oracle and the metrics, the navigator on the map
  if (scenario.mode == RunMode::kNavigate) {
    truth_W_ = options.world != nullptr ? options.world->truth_W
                                        : WorldGroundTruth(scenario, world_, obstacle_heights());
    // the robot's outline from the robot file, for the search and the optimiser alike
    planner::NavigationPlannerConfig planner = scenario.planner;
    planner.footprint = simulation_->RobotFootprint();
    // the ground ends at the world's edge
    planner.search.operating_area_W.emplace(world_.geometry.origin_W,
                                            world_.geometry.origin_W + world_.geometry.Extent());
    navigator_.emplace(scenario.navigation, planner, scenario.mpc, scenario.goal_W,
                       FindPathSearch(scenario.planner_method)(scenario),
                       FindController(scenario.controller_method)(scenario));
    if (oracle) navigation_map_ = &*truth_W_;
    // movers perceived from the scans, when the scenario does not give the planner their state
    if (lidar_ && !scenario.navigation.movers_from_ground_truth) {
      mapping::MoverTrackerConfig tracker_config;
      tracker_config.range_m = scenario.navigation.mover_sensing_range_m;
      mover_tracker_.emplace(tracker_config);
    }
  }
  if (scenario.imu.enabled && simulation_->ImuTruth()) imu_.emplace(scenario.imu);
  pose_noise_.emplace(scenario.pose_noise);
  if (lidar_ && scenario.pose_noise.method == sim::LocalizationMethod::kScanMatching) {
    // O is where the sensor starts; the sensor's mount is fixed on the base
    const Eigen::Isometry3d X_WB = simulation_->State().X_WB;
    X_BL_odometry_ = lidar_mount_B();
    odometry_ =
        std::make_unique<mapping::LidarOdometry>(scenario.lidar_odometry, X_WB * X_BL_odometry_);
  }
  total_steps_ = static_cast<int>(std::ceil(scenario.duration_s / simulation_->timestep() - 1e-9));
  state_ = simulation_->State();
}

ClosedLoop::~ClosedLoop() = default;

const Eigen::MatrixXf& ClosedLoop::obstacle_heights() const {
  if (!obstacle_heights_) obstacle_heights_ = sim::ObstacleHeightGrid(world_);
  return *obstacle_heights_;
}

void ClosedLoop::AddObserver(LoopObserver* observer) {
  observers_.push_back(observer);
  observers_want_points_ = observers_want_points_ || observer->WantsPoints();
}

void ClosedLoop::AddEndCondition(std::unique_ptr<EndCondition> condition) {
  end_conditions_.push_back(std::move(condition));
}

void ClosedLoop::PlaceMovers() {
  sim::Simulation& simulation = *simulation_;
  if (simulation.num_movers() == 0) return;
  const double dt = simulation.timestep();
  simulation.SetMoverPoses(simulation.time());
  if (!crowd_.empty()) {
    // reactive walkers: the social force from the movers and the robot where they are now
    std::vector<Eigen::Vector2d> positions_W;
    for (int i = 0; i < simulation.num_movers(); ++i) {
      positions_W.push_back(simulation.MoverPose(i).translation().head<2>());
    }
    crowd_.Step(simulation.time(), dt, positions_W, state_.X_WB.translation().head<2>(),
                scenario_.planner.optimizer.robot_radius_m);
    for (const sim::SocialForceCrowd::Walker& walker : crowd_.walkers()) {
      const sim::MoverPlanarState planar{walker.p_W, walker.v_W, walker.yaw};
      simulation.SetMoverPose(static_cast<int>(walker.index),
                              sim::MoverPose(movers_[walker.index], planar, world_), walker.v_W);
    }
  }
}

void ClosedLoop::DecideCommand() {
  const double now_s = simulation_->time();
  // the one pose estimate of this step, for the navigator, the mapper and the mover tracker
  estimate_ = EstimatePose();
  if (!navigator_) {
    command_ = tracker_ ? tracker_->Command(state_) : DriveCommandAt(scenario_.drive, now_s);
    return;
  }
  // the planner's predictions: the true movers, or those perceived in the scans (false
  // positives included: they reach the planner whether or not true movers exist)
  true_movers_ = TrueMovers(movers_, *simulation_, now_s);
  predicted_movers_ = mover_tracker_ ? PerceivedMovers(*mover_tracker_) : true_movers_;
  // the navigator's wall time goes to planning when it planned, else to control when the MPC
  // solved (the other ticks hold the command)
  const common::Stopwatch navigation_start;
  navigator_tick_ = navigator_->Update(estimate_, navigation_map_, map_changed_, predicted_movers_);
  const double navigation_ms = navigation_start.ElapsedMilliseconds();
  if (navigator_tick_.replan != planner::ReplanReason::kNone) {
    times_.Add("planning", navigation_ms);
  } else if (navigator_tick_.solved) {
    times_.Add("control", navigation_ms);
  }
  map_changed_ = false;
  command_ = navigator_tick_.command;
}

bool ClosedLoop::Scan() {
  const sim::Simulation& simulation = *simulation_;
  ScanStep step;
  step.t_begin_s = simulation.time();
  step.t_end_s = simulation.time() + simulation.timestep();
  step.X_WL = X_BL_ ? Eigen::Isometry3d(state_.X_WB * *X_BL_) : simulation.LidarPose();
  // the movers where they are at this step (the ray scene holds every mover of the simulation)
  for (int i = 0; i < simulation.num_movers(); ++i) {
    step.movers_X_WI.push_back(simulation.MoverPose(i));
  }
  if (!lidar_->Submit(std::move(step))) return true;
  lidar_->TakeFrame(&lidar_frame_);
  TakeScanTimes();
  ++lidar_frames_;
  if (odometry_) RegisterScan();
  lidar_points_ += static_cast<double>(lidar_frame_.points_L.size());
  // the frame in W, each point placed with its own sensor pose: once for everything that wants it
  common::PointCloud cloud_W;
  if (observers_want_points_ || mapping_ || mover_tracker_) {
    cloud_W.points = lidar::PointsInWorld(lidar_frame_);
    cloud_W.stamp_s = lidar_frame_.points_L.stamp_s;
  }
  for (LoopObserver* observer : observers_) {
    observer->OnLidarFrame(*this, lidar_frame_, cloud_W.points);
  }
  // the stack sees the frame in the odometry frame O of its pose estimate (W with true poses)
  common::PointCloud cloud_O = std::move(cloud_W);
  const Eigen::Isometry3d X_OW = OdometryFromWorld();
  if (scenario_.pose_noise.active()) {
    const Eigen::Isometry3f X_OW_f = X_OW.cast<float>();
    cloud_O.points = (X_OW_f.linear() * cloud_O.points).colwise() + X_OW_f.translation();
  }
  if (mover_tracker_) {
    mover_tracker_->Update(cloud_O, estimate_.X_WB.translation(), simulation.time());
  }
  // movers are removed at scan time: where the tracker perceives them, or with their true poses
  // when the planner gets those
  if (mapping_ || observers_want_points_) {
    RemovePointsInDiscs(mover_tracker_ ? PerceivedMoverDiscs(*mover_tracker_, simulation.time())
                                       : TrueMoverDiscs(movers_, simulation, X_OW),
                        &cloud_O);
    for (LoopObserver* observer : observers_) {
      observer->OnMapInput(*this, cloud_O, estimate_.X_WB, simulation.time());
    }
  }
  if (mapping_) {
    // the frame's map takes effect after the modelled latency
    mapping_->Submit({simulation.time() + scenario_.navigation.mapping_latency_s,
                      std::move(cloud_O), estimate_.X_WB, simulation.time()});
  }
  return max_lidar_frames_ <= 0 || lidar_frames_ < max_lidar_frames_;
}

void ClosedLoop::TakeScanTimes() {
  scan_ms_.clear();
  lidar_->TakeStepTimes(&scan_ms_);
  for (const double ms : scan_ms_) {
    lidar_cast_s_ += 1e-3 * ms;
    times_.Add("lidar", ms);
  }
}

common::RobotState ClosedLoop::EstimatePose() {
  if (!odometry_) return pose_noise_->Estimate(state_);
  common::RobotState estimate = state_;
  // between scans the motion since the last one carries the estimate on, as an IMU would
  if (last_scan_pose_) {
    estimate.X_WB = last_scan_pose_->X_OB * (last_scan_pose_->X_WB.inverse() * state_.X_WB);
  }
  return estimate;
}

void ClosedLoop::RegisterScan() {
  const common::Stopwatch start;
  std::optional<Eigen::Matrix3d> R_turn;
  if (imu_) {
    const Eigen::Matrix3d& R_BL = X_BL_odometry_.linear();
    R_turn = R_BL.transpose() * gyro_turn_B_ * R_BL;
    gyro_turn_B_.setIdentity();
  }
  const Eigen::Isometry3d& X_OL =
      odometry_->AddScan(lidar_frame_.points_L.points, lidar_frame_.points_L.time_offsets,
                         scenario_.lidar.frame_period_s, R_turn);
  times_.Add("localization", start.ElapsedMilliseconds());
  last_scan_pose_ = ScanPose{X_OL * X_BL_odometry_.inverse(), state_.X_WB};
  estimate_.X_WB = last_scan_pose_->X_OB;
}

Eigen::Isometry3d ClosedLoop::lidar_mount_B() const {
  return X_BL_ ? *X_BL_
               : Eigen::Isometry3d(simulation_->State().X_WB.inverse() * simulation_->LidarPose());
}

Eigen::Isometry3d ClosedLoop::OdometryFromWorld() const {
  return scenario_.pose_noise.active() ? estimate_.X_WB * state_.X_WB.inverse()
                                       : Eigen::Isometry3d::Identity();
}

void ClosedLoop::MapPendingFrames() {
  if (!mapping_) return;
  while (std::optional<MapUpdate> update = mapping_->NextDue(simulation_->time())) {
    map_updates_.push_back(update->result);
    mapping_ms_.push_back(update->mapping_ms);
    times_.Add("mapping", update->mapping_ms);
    navigation_map_ = mapping_->map();
    map_changed_ = true;
    if (truth_W_) {
      last_mapping_error_ =
          CompareWithTruth(*mapping_->map(), *truth_W_, mapping::layers::kTraversability).mean;
    }
    for (LoopObserver* observer : observers_) observer->OnMapUpdate(*this);
  }
}

std::optional<Outcome> ClosedLoop::CheckEnd(EndCondition::Stage stage, const LoopStep& step) {
  for (const std::unique_ptr<EndCondition>& condition : end_conditions_) {
    if (condition->stage() != stage) continue;
    if (const std::optional<Outcome> outcome = condition->Check(*this, step)) return outcome;
  }
  return std::nullopt;
}

Outcome ClosedLoop::Run(const std::function<void(double fraction)>& progress) {
  sim::Simulation& simulation = *simulation_;
  const double dt = simulation.timestep();
  Outcome outcome = Outcome::kCompleted;
  int progress_step = 0;
  for (int index = 0; index < total_steps_; ++index) {
    PlaceMovers();
    DecideCommand();
    for (LoopObserver* observer : observers_) observer->OnCommand(*this);
    simulation.SetWheelSpeedCommands(controller::ToWheelSpeeds(command_, scenario_.skid_steer));
    if (lidar_ && !Scan()) break;
    MapPendingFrames();
    for (LoopObserver* observer : observers_) observer->BeforePhysics(*this);

    const common::Stopwatch physics_start;
    const double step_start_s = simulation.time();
    const sim::StepStatus status = simulation.Step();
    times_.Add("physics", physics_start.ElapsedMilliseconds());
    // MuJoCo's sensors of this step read the state at its start
    if (imu_) {
      imu_->AddReading(step_start_s, *simulation.ImuTruth());
      if (odometry_)
        gyro_turn_B_ = sim::IntegrateGyro(gyro_turn_B_, imu_->samples(), scenario_.imu.rate_hz);
    }
    ++physics_steps_;
    if (status == sim::StepStatus::kDiverged) {
      outcome = Outcome::kDiverged;
      break;
    }
    state_ = simulation.State();
    LoopStep step;
    step.index = index;
    step.state = state_;
    step.rpy = common::ToRollPitchYaw(state_.X_WB.linear());
    step.command = command_;
    const double vertical_speed = (state_.X_WB.linear() * state_.v_WB_B).z();
    step.vertical_acceleration_m_s2 = (vertical_speed - previous_vertical_speed_m_s_) / dt;
    previous_vertical_speed_m_s_ = vertical_speed;
    step.last = index + 1 == total_steps_;
    for (LoopObserver* observer : observers_) observer->OnPhysicsStep(*this, step);
    std::optional<Outcome> end = CheckEnd(EndCondition::Stage::kPhysical, step);
    if (!end) {
      for (LoopObserver* observer : observers_) observer->OnStepChecked(*this, step);
      end = CheckEnd(EndCondition::Stage::kMission, step);
    }
    if (end) {
      outcome = *end;
      break;
    }
    if (progress && (index - progress_step) * dt >= 0.5) {
      progress_step = index;
      progress(static_cast<double>(index + 1) / total_steps_);
    }
  }
  if (lidar_) TakeScanTimes();
  if (progress) progress(1.0);
  for (LoopObserver* observer : observers_) observer->OnEnd(*this, outcome);
  return outcome;
}

}  // namespace trav::scenarios
