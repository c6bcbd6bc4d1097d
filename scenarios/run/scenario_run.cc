#include "scenarios/run/scenario_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "common/statistics.h"
#include "controller/mpc_tracker.h"
#include "controller/skid_steer.h"
#include "mapping/ground_truth.h"
#include "mapping/mover_tracker.h"
#include "planner/astar.h"
#include "planner/navigation/navigator.h"
#include "renders/image.h"
#include "renders/map_panel.h"
#include "renders/renderer.h"
#include "renders/video_writer.h"
#include "scenarios/run/mappers.h"
#include "scenarios/run/output_folder.h"
#include "scenarios/run/pcd_io.h"
#include "scenarios/run/plots.h"
#include "scenarios/run/provenance.h"
#include "scenarios/run/run_metrics.h"
#include "sim/actors/social_force.h"
#include "sim/lidar/lidar_emulator.h"
#include "sim/simulation.h"
#include "sim/terrain_geometry.h"

namespace trav::scenarios {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
constexpr double kTrajectoryPeriod_s = 0.02;
// The modules timed per run, as named in summary.json's "compute" and timeseries.csv.
constexpr const char* kTimedModules[] = {"lidar",   "mapping", "planning",
                                         "control", "physics", "render"};

// The video camera for the scenario's camera mode.
class VideoCamera {
 public:
  VideoCamera(renders::CameraMode mode, const sim::TerrainWorld& world) : mode_(mode) {
    const Eigen::Vector2d centre = world.geometry.Center();
    overview_ = renders::OverviewView(
        Eigen::Vector3d(centre.x(), centre.y(), world.height_m.mean()), world.geometry.Extent());
  }
  renders::CameraView View(const Eigen::Isometry3d& X_WB, double dt_s) {
    switch (mode_) {
      case renders::CameraMode::kChase:
        return chase_.Update(X_WB, dt_s);
      case renders::CameraMode::kOverview:
        return overview_;
      case renders::CameraMode::kTopDown:
        return renders::TopDownView(X_WB.translation(), 8.0);
    }
    return overview_;
  }

 private:
  renders::CameraMode mode_;
  renders::ChaseCamera chase_;
  renders::CameraView overview_;
};

// LiDAR points drawn in a video frame: at most this many (each is one geom, drawn one by one by
// MuJoCo's renderer), and only within this distance of the sensor (where a chase camera sees them).
constexpr Eigen::Index kMaxDrawnPoints = 1200;
// Segments of the planned path drawn in a video frame, at most.
constexpr std::size_t kMaxPlanSegments = 60;
constexpr float kDrawnPointRange_m = 15.0f;

// The latest LiDAR frame's points (`points_W`: the frame placed in W) near the sensor, coloured by
// height (blue low, red high), evenly subsampled.
renders::ColoredPoints DrawablePoints(const lidar::LidarFrame& frame,
                                      const Eigen::Matrix3Xf& points_W) {
  std::vector<Eigen::Index> near;
  for (Eigen::Index i = 0; i < points_W.cols(); ++i) {
    if (frame.points_L.points.col(i).norm() < kDrawnPointRange_m) near.push_back(i);
  }
  const std::size_t stride =
      std::max<std::size_t>(1, (near.size() + kMaxDrawnPoints - 1) / kMaxDrawnPoints);
  const auto count = static_cast<Eigen::Index>((near.size() + stride - 1) / stride);
  renders::ColoredPoints drawable;
  drawable.radius_m = 0.03;
  drawable.points_W.resize(3, count);
  drawable.rgba.resize(4, count);
  for (Eigen::Index k = 0; k < count; ++k)
    drawable.points_W.col(k) = points_W.col(near[static_cast<std::size_t>(k) * stride]);
  if (count == 0) return drawable;
  const float low = drawable.points_W.row(2).minCoeff();
  const float range = std::max(0.5f, drawable.points_W.row(2).maxCoeff() - low);
  for (Eigen::Index k = 0; k < count; ++k) {
    const float t = (drawable.points_W(2, k) - low) / range;
    drawable.rgba.col(k) =
        Eigen::Vector4f(t, 0.3f + 0.4f * (1.0f - std::abs(2.0f * t - 1.0f)), 1.0f - t, 1.0f);
  }
  return drawable;
}

// The traversability layer as a coloured ground grid at the map's elevation.
renders::GroundGrid DrawableMap(const common::GridLayers& map) {
  renders::GroundGrid grid;
  grid.geometry = map.geometry();
  grid.values = map.Layer(mapping::layers::kTraversability);
  grid.heights_m = map.Layer(mapping::layers::kElevation);
  grid.alpha = 0.55f;
  grid.max_cells = 3000;
  return grid;
}

// The top-down panel of the closed loop: the navigation map around the robot, the plan (white),
// the driven path (blue), the goal (magenta), the movers (orange), the robot (black) and the latest
// LiDAR points.
renders::PanelOverlay NavigationPanel(const planner::Navigator& navigator,
                                      const std::vector<Eigen::Vector2d>& driven_W,
                                      const Eigen::Vector2d& goal_W,
                                      const common::RobotState& state,
                                      const std::vector<planner::MovingObstacle>& movers,
                                      const Eigen::Matrix3Xf& points_W) {
  renders::PanelOverlay panel;
  renders::PanelPath planned;
  for (const common::TrajectoryPoint& p : navigator.trajectory().points()) {
    planned.points_W.push_back(p.position_W);
  }
  planned.rgb = Eigen::Vector3i(255, 255, 255);
  panel.paths.push_back(std::move(planned));
  panel.paths.push_back({driven_W, Eigen::Vector3i(30, 90, 255), 2});
  const Eigen::Index stride = std::max<Eigen::Index>(1, points_W.cols() / 3000);
  for (Eigen::Index i = 0; i < points_W.cols(); i += stride) {
    panel.points_W.push_back(points_W.col(i).head<2>().cast<double>());
  }
  panel.discs.push_back({goal_W, 0.4, Eigen::Vector3i(230, 0, 230), true});
  for (const planner::MovingObstacle& mover : movers) {
    panel.discs.push_back(
        {mover.PositionAt(state.time_s), mover.radius_m, Eigen::Vector3i(255, 140, 0), true});
  }
  panel.discs.push_back({state.X_WB.translation().head<2>(), 0.3, Eigen::Vector3i(0, 0, 0), true});
  return panel;
}

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

// Who closed the gap at a contact: the robot if it approached the mover at least as fast as the
// mover approached it (and was moving), else the mover.
std::string CollisionCause(const Eigen::Vector2d& robot_W, const Eigen::Vector2d& v_robot_W,
                           const Eigen::Vector2d& mover_W, const Eigen::Vector2d& v_mover_W) {
  constexpr double kStopped_m_s = 0.05;
  const Eigen::Vector2d towards_mover = (mover_W - robot_W).normalized();
  const double robot_approach = v_robot_W.dot(towards_mover);
  const double mover_approach = -v_mover_W.dot(towards_mover);
  return v_robot_W.norm() > kStopped_m_s && robot_approach >= mover_approach ? "robot" : "mover";
}

// The movers the planner perceived: the tracker's moving tracks, at constant velocity from their
// last update.
std::vector<planner::MovingObstacle> PerceivedMovers(const mapping::MoverTracker& tracker) {
  std::vector<planner::MovingObstacle> movers;
  for (const mapping::TrackedMover& track : tracker.Movers()) {
    movers.push_back({track.position_W, track.velocity_W, track.radius_m, track.t_s});
  }
  return movers;
}

// A disc in W: where a mover stands.
struct Disc {
  Eigen::Vector2d centre_W;
  double radius_m;
};

// The movers' footprints from their true poses.
std::vector<Disc> TrueMoverDiscs(const std::vector<sim::MovingObstacle>& movers,
                                 const sim::Simulation& simulation) {
  std::vector<Disc> discs;
  for (int k = 0; k < simulation.num_movers(); ++k) {
    discs.push_back({simulation.MoverPose(k).translation().head<2>(),
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
void RemovePointsInDiscs(const std::vector<Disc>& discs, common::PointCloud* cloud_W) {
  constexpr double kMargin_m = 0.3;
  if (discs.empty()) return;
  Eigen::Index kept = 0;
  for (Eigen::Index i = 0; i < cloud_W->size(); ++i) {
    const Eigen::Vector2d p = cloud_W->points.col(i).head<2>().cast<double>();
    const bool on_mover = std::any_of(discs.begin(), discs.end(), [&](const Disc& disc) {
      const double reach = disc.radius_m + kMargin_m;
      return (p - disc.centre_W).squaredNorm() < reach * reach;
    });
    if (!on_mover) cloud_W->points.col(kept++) = cloud_W->points.col(i);
  }
  cloud_W->points.conservativeResize(3, kept);
  cloud_W->time_offsets.resize(0);
  cloud_W->line_ids.resize(0);
}

// A LiDAR frame on its way to the mapper (mapping latency).
struct PendingFrame {
  double ready_s;  // simulation time at which the mapper gets it
  common::PointCloud cloud_W;
  Eigen::Isometry3d X_WB;
  double scan_time_s;
};

double MillisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace

std::vector<sim::MovingObstacle> ScenarioMovers(const Scenario& scenario,
                                                const sim::TerrainWorld& world,
                                                const Eigen::MatrixXf& obstacle_heights) {
  std::vector<sim::MovingObstacle> movers = scenario.movers;
  if (scenario.traffic.count == 0) return movers;
  // free: no obstacle surface on the world's height grid within the disc
  const common::GridGeometry& g = world.geometry;
  auto free = [&](const Eigen::Vector2d& centre_W, double radius_m) {
    const int reach = static_cast<int>(std::ceil(radius_m / g.resolution_m));
    const std::optional<Eigen::Vector2i> centre = g.CellIndex(centre_W);
    if (!centre) return true;  // off the terrain: nothing to walk into
    for (int ix = centre->x() - reach; ix <= centre->x() + reach; ++ix) {
      for (int iy = centre->y() - reach; iy <= centre->y() + reach; ++iy) {
        if (!g.Contains(ix, iy) || (g.CellCenter(ix, iy) - centre_W).norm() > radius_m) continue;
        if (obstacle_heights(ix, iy) > 0.0f) return false;
      }
    }
    return true;
  };
  const std::vector<sim::MovingObstacle> traffic =
      sim::SpawnTraffic(scenario.traffic, scenario.start_W.position, scenario.goal_W, free);
  movers.insert(movers.end(), traffic.begin(), traffic.end());
  return movers;
}

common::GridLayers WorldGroundTruth(const Scenario& scenario, const sim::TerrainWorld& world,
                                    const Eigen::MatrixXf& obstacle_heights) {
  const common::GridGeometry geometry = common::GridGeometry::Centered(
      world.geometry.Center(), world.geometry.Extent(), scenario.mapping.area.resolution_m);
  return mapping::ComputeGroundTruth(geometry, world.geometry, world.height_m, obstacle_heights,
                                     scenario.mapping, scenario.ground_truth);
}

double OptimalPathLength(const Scenario& scenario, const common::GridLayers& truth) {
  const planner::GridPlanner search(truth, scenario.planner.search);
  const planner::GridPath path = search.Plan(scenario.start_W.position, scenario.goal_W);
  if (path.status != planner::PlanStatus::kFound) return 0.0;
  std::vector<Eigen::Vector2d> waypoints =
      search.Simplify(path.points_W, scenario.planner.simplify_tolerance);
  waypoints.front() = scenario.start_W.position;
  waypoints.back() = scenario.goal_W;
  double length = 0.0;
  for (std::size_t i = 1; i < waypoints.size(); ++i)
    length += (waypoints[i] - waypoints[i - 1]).norm();
  return length;
}

std::string RobotModelPath(const Scenario& scenario, const std::string& models_dir) {
  const std::filesystem::path model(scenario.robot_model);
  return model.is_absolute() ? model.string()
                             : (std::filesystem::path(models_dir) / model).string();
}

RunSummary RunScenario(const Scenario& scenario, const std::string& robot_model_path,
                       const std::string& output_dir, const RunOptions& run_options,
                       const ProgressCallback& progress) {
  const auto wall_start = std::chrono::steady_clock::now();
  const sim::TerrainWorld world =
      sim::GenerateTerrain(scenario.terrain, {scenario.start_W.position, scenario.goal_W});

  // what drives the robot: the script, or the MPC tracking a reference that starts at the robot
  std::optional<controller::MpcTracker> tracker;
  common::Pose2 start_W = scenario.start_W;
  if (scenario.mode == RunMode::kTrack) {
    tracker.emplace(scenario.mpc, BuildReference(scenario.track, scenario.start_W));
    const common::TrajectoryPoint first =
        tracker->reference().Sample(tracker->reference().start_time());
    start_W.position = first.position_W;
    start_W.yaw = first.yaw;
  }
  sim::WorldOptions options;
  options.robot_model_path = robot_model_path;
  options.timestep_s = scenario.physics_timestep_s;
  options.ground_friction = scenario.ground_friction;
  // the world's obstacle heights, computed once when first needed (traffic, ground truth)
  std::optional<Eigen::MatrixXf> obstacle_heights_cache;
  auto obstacle_heights = [&]() -> const Eigen::MatrixXf& {
    if (!obstacle_heights_cache) obstacle_heights_cache = sim::ObstacleHeightGrid(world);
    return *obstacle_heights_cache;
  };
  const std::vector<sim::MovingObstacle> movers =
      scenario.traffic.count > 0 ? ScenarioMovers(scenario, world, obstacle_heights())
                                 : scenario.movers;
  sim::Simulation simulation(world, start_W, options, movers);
  sim::SocialForceCrowd crowd(movers);

  // LiDAR: an Embree scene of the same world, scanned every physics step
  std::unique_ptr<lidar::RayScene> ray_scene;
  std::unique_ptr<lidar::LidarEmulator> lidar;
  lidar::LidarFrame lidar_frame;
  renders::Overlay overlay;
  // the sensor pose: the scenario's mount on the base, or the model's lidar site
  const bool mounted = scenario.lidar_mount_B.has_value();
  const Eigen::Isometry3d X_BL =
      mounted ? MountPose(*scenario.lidar_mount_B) : Eigen::Isometry3d::Identity();
  if (scenario.lidar.enabled) {
    ray_scene = std::make_unique<lidar::RayScene>(sim::RaySceneOf(world, movers));
    lidar = std::make_unique<lidar::LidarEmulator>(scenario.lidar);
    if (run_options.record_clouds) std::filesystem::create_directories(output_dir + "/clouds");
  }
  // tracking: the reference path on the ground in videos
  if (tracker && scenario.video.enabled) {
    const std::vector<common::TrajectoryPoint>& points = tracker->reference().points();
    renders::Polyline path;
    path.rgba = Eigen::Vector4f(0.1f, 0.4f, 1.0f, 1.0f);
    const std::size_t stride = std::max<std::size_t>(1, points.size() / 400);
    for (std::size_t i = 0; i < points.size(); i += stride) {
      const Eigen::Vector2d& p = points[i].position_W;
      path.points_W.emplace_back(p.x(), p.y(), world.GroundHeight(p) + 0.02);
    }
    overlay.polylines.push_back(std::move(path));
  }
  double lidar_cast_s = 0.0;
  double lidar_points = 0.0;
  // mapping: every LiDAR frame, in W with each point's own sensor pose
  const bool navigate = scenario.mode == RunMode::kNavigate;
  const bool oracle = scenario.mapper == MapperMethod::kGroundTruth;
  std::unique_ptr<mapping::TraversabilityMapper> mapper;
  if (lidar && scenario.mapping_enabled && !oracle) mapper = MakeMapper(scenario);
  std::vector<double> mapping_ms;
  std::vector<mapping::MapUpdateResult> map_updates;
  ModuleTimes times;

  // the closed loop: the ground truth for the oracle and the metrics, the navigator on the map
  std::optional<common::GridLayers> truth_W;
  std::optional<planner::Navigator> navigator;
  NavigationMetrics navigation;
  const common::GridLayers* navigation_map = nullptr;
  bool map_changed = false;
  std::optional<ProgressMonitor> progress_monitor;
  std::ofstream timeseries;
  if (navigate) {
    truth_W = WorldGroundTruth(scenario, world, obstacle_heights());
    navigation.optimal_path_length_m = OptimalPathLength(scenario, *truth_W);
    navigator.emplace(scenario.navigation, scenario.planner, scenario.mpc, scenario.goal_W);
    progress_monitor.emplace(scenario.navigation.stuck_time_s,
                             scenario.navigation.stuck_distance_m);
    if (oracle) navigation_map = &*truth_W;
    timeseries.open(output_dir + "/timeseries.csv");
    timeseries
        << "t,x,y,yaw,v_forward,yaw_rate,roll_deg,pitch_deg,vertical_acceleration,cmd_v,"
           "cmd_omega,goal_distance,mapping_error,lidar_ms,mapping_ms,planning_ms,control_ms,"
           "physics_ms,render_ms\n";
  }
  std::vector<planner::MovingObstacle> predicted_movers;
  std::vector<bool> near_miss;  // per mover: within the near-miss clearance now
  double tracking_error_sum = 0.0;
  int tracking_error_count = 0;
  std::vector<sim::RobotContact> contacts;
  std::map<std::string, double> module_totals_ms;
  std::deque<PendingFrame> pending_frames;
  std::optional<sim::PoseNoise> localization;
  if (navigate) localization.emplace(scenario.pose_noise);
  // movers perceived from the scans, when the scenario does not give the planner their true state
  std::optional<mapping::MoverTracker> mover_tracker;
  if (navigate && lidar && !scenario.navigation.movers_from_ground_truth) {
    mapping::MoverTrackerConfig tracker_config;
    tracker_config.range_m = scenario.navigation.mover_sensing_range_m;
    mover_tracker.emplace(tracker_config);
  }
  std::vector<Eigen::Vector2d> driven_W = {scenario.start_W.position};
  Eigen::Matrix3Xf latest_points_W;
  double sum_vertical_acceleration2 = 0.0;
  double previous_vertical_speed = 0.0;
  double last_mapping_error = std::nan("");

  // video: renderer and encoder only when asked for
  std::unique_ptr<renders::Renderer> renderer;
  std::unique_ptr<renders::VideoWriter> video;
  std::optional<VideoCamera> camera;
  renders::Image frame;
  if (scenario.video.enabled) {
    renderer = std::make_unique<renders::Renderer>(&simulation, scenario.video.render);
    // the closed loop adds a square map panel to the right of the camera's view
    const int panel_px = scenario.mode == RunMode::kNavigate ? scenario.video.render.height : 0;
    video = std::make_unique<renders::VideoWriter>(
        output_dir + "/video.mp4", scenario.video.render.width + panel_px,
        scenario.video.render.height, scenario.video.fps);
    camera.emplace(scenario.video.camera, world);
  }
  const double frame_period_s = 1.0 / scenario.video.fps;
  double next_frame_s = 0.0;
  // a navigation frame: the camera's view with a status line, and the map panel beside it
  const Eigen::MatrixXf no_map =
      truth_W ? Eigen::MatrixXf::Constant(truth_W->geometry().num_x, truth_W->geometry().num_y, NAN)
              : Eigen::MatrixXf();
  auto write_navigation_frame = [&](const common::RobotState& now, const std::string& status) {
    char text[256];
    std::snprintf(text, sizeof(text), "t %.1f s   v %.2f m/s   goal %.1f m   %s", now.time_s,
                  now.v_WB_B.x(), (now.X_WB.translation().head<2>() - scenario.goal_W).norm(),
                  status.c_str());
    overlay.texts.assign(1, renders::TextLabel{text, renders::TextCorner::kTopLeft});
    renderer->Render(simulation, camera->View(now.X_WB, frame_period_s), overlay, &frame);
    const common::GridLayers& shown = navigation_map != nullptr ? *navigation_map : *truth_W;
    const Eigen::MatrixXf& layer =
        navigation_map != nullptr ? shown.Layer(mapping::layers::kTraversability) : no_map;
    const renders::Image panel =
        renders::DrawMapPanel(shown, layer, now.X_WB.translation().head<2>(),
                              scenario.mapping.area.map_size_m, frame.height,
                              NavigationPanel(*navigator, driven_W, scenario.goal_W, now,
                                              predicted_movers, latest_points_W));
    video->Write(renders::SideBySide(frame, panel));
  };
  const int steps_per_sample =
      std::max(1, static_cast<int>(std::lround(kTrajectoryPeriod_s / simulation.timestep())));

  const double dt = simulation.timestep();
  std::ofstream trajectory(output_dir + "/trajectory.csv");
  trajectory << "t,x,y,z,roll,pitch,yaw,v_forward,yaw_rate,cmd_v,cmd_omega,"
                "wheel_fl,wheel_rl,wheel_fr,wheel_rr\n";

  RunSummary summary;
  const int total_steps = static_cast<int>(std::ceil(scenario.duration_s / dt - 1e-9));
  const double tilt_limit = scenario.rollover_limit_deg / kRadToDeg;
  double sum_roll2 = 0.0;
  double sum_pitch2 = 0.0;
  common::RobotState state = simulation.State();
  Eigen::Vector2d last_xy = state.X_WB.translation().head<2>();
  int progress_step = 0;

  for (int step = 0; step < total_steps; ++step) {
    // movers to their place at this time, for physics and LiDAR
    if (simulation.num_movers() > 0) {
      simulation.SetMoverPoses(simulation.time());
      if (!crowd.empty()) {
        // reactive walkers: the social force from the movers and the robot where they are now
        std::vector<Eigen::Vector2d> positions_W;
        for (int i = 0; i < simulation.num_movers(); ++i) {
          positions_W.push_back(simulation.MoverPose(i).translation().head<2>());
        }
        crowd.Step(simulation.time(), dt, positions_W, state.X_WB.translation().head<2>(),
                   scenario.planner.optimizer.robot_radius_m);
        for (const sim::SocialForceCrowd::Walker& walker : crowd.walkers()) {
          const sim::MoverPlanarState planar{walker.p_W, walker.v_W, walker.yaw};
          simulation.SetMoverPose(static_cast<int>(walker.index),
                                  sim::MoverPose(movers[walker.index], planar, world), walker.v_W);
        }
      }
      for (int i = 0; i < simulation.num_movers(); ++i) {
        if (ray_scene) ray_scene->SetMovingPose(i, simulation.MoverPose(i));
      }
    }
    // the planner's predictions: the true movers, or those perceived in the scans (false
    // positives included: they reach the planner whether or not true movers exist)
    if (navigator) {
      const std::vector<planner::MovingObstacle> true_movers =
          TrueMovers(movers, simulation, simulation.time());
      near_miss.resize(true_movers.size(), false);
      for (std::size_t k = 0; k < true_movers.size(); ++k) {
        const planner::MovingObstacle& mover = true_movers[k];
        const double gap = (mover.position_W - state.X_WB.translation().head<2>()).norm() -
                           mover.radius_m - scenario.planner.optimizer.robot_radius_m;
        navigation.min_mover_clearance_m = std::min(navigation.min_mover_clearance_m, gap);
        if (!near_miss[k] && gap < scenario.navigation.near_miss_clearance_m) {
          near_miss[k] = true;
          ++navigation.near_misses;
        } else if (near_miss[k] && gap > scenario.navigation.near_miss_clearance_m + 0.1) {
          near_miss[k] = false;
        }
      }
      if (mover_tracker) {
        predicted_movers = PerceivedMovers(*mover_tracker);
        // each perceived mover against the nearest true one, now
        for (const planner::MovingObstacle& seen : predicted_movers) {
          double nearest = std::numeric_limits<double>::infinity();
          for (const planner::MovingObstacle& mover : true_movers) {
            nearest =
                std::min(nearest, (seen.PositionAt(simulation.time()) - mover.position_W).norm());
          }
          if (nearest <= kFalseMoverDistance_m) {
            tracking_error_sum += nearest;
            ++tracking_error_count;
          } else {
            ++navigation.false_mover_samples;
          }
        }
      } else {
        predicted_movers = true_movers;
      }
    }
    common::Twist2 command;
    if (navigator) {
      // the navigator's wall time goes to planning when it planned, else to control when the MPC
      // solved (the other ticks hold the command)
      const planner::Navigator::Statistics& stats = navigator->statistics();
      const int plans_before = stats.plans;
      const std::size_t solves_before = stats.control_ms.size();
      const auto navigation_start = std::chrono::steady_clock::now();
      command = navigator->Update(localization->Estimate(state), navigation_map, map_changed,
                                  predicted_movers);
      const double navigation_ms = MillisecondsSince(navigation_start);
      if (stats.plans > plans_before) {
        times.Add("planning", navigation_ms);
      } else if (stats.control_ms.size() > solves_before) {
        times.Add("control", navigation_ms);
      }
      map_changed = false;
    } else {
      command =
          tracker ? tracker->Command(state) : DriveCommandAt(scenario.drive, simulation.time());
    }
    simulation.SetWheelSpeedCommands(controller::ToWheelSpeeds(command, scenario.skid_steer));

    if (lidar) {
      const Eigen::Isometry3d X_WL =
          mounted ? Eigen::Isometry3d(state.X_WB * X_BL) : simulation.LidarPose();
      const auto cast_start = std::chrono::steady_clock::now();
      lidar->Scan(*ray_scene, simulation.time(), simulation.time() + dt, X_WL);
      const double cast_ms = MillisecondsSince(cast_start);
      lidar_cast_s += 1e-3 * cast_ms;
      times.Add("lidar", cast_ms);
      if (lidar->frame_ready()) {
        lidar->TakeFrame(&lidar_frame);
        ++summary.lidar_frames;
        lidar_points += static_cast<double>(lidar_frame.points_L.size());
        if (run_options.record_clouds) {
          char name[64];
          std::snprintf(name, sizeof(name), "/clouds/frame_%06lld.pcd",
                        static_cast<long long>(lidar_frame.index));
          WriteLidarFramePcd(output_dir + name, lidar_frame);
        }
        // the frame in W, each point placed with its own sensor pose: once for video and mapping
        common::PointCloud cloud_W;
        if (video || mapper || mover_tracker || run_options.on_lidar_frame) {
          cloud_W.points = lidar::PointsInWorld(lidar_frame);
          cloud_W.stamp_s = lidar_frame.points_L.stamp_s;
        }
        if (video) {
          overlay.points.assign(1, DrawablePoints(lidar_frame, cloud_W.points));
          if (navigator) latest_points_W = cloud_W.points;
        }
        if (mover_tracker) {
          mover_tracker->Update(cloud_W, state.X_WB.translation(), simulation.time());
        }
        // movers are removed at scan time: where the tracker perceives them, or with their true
        // poses when the planner gets those
        if (mapper || run_options.on_lidar_frame) {
          RemovePointsInDiscs(mover_tracker ? PerceivedMoverDiscs(*mover_tracker, simulation.time())
                                            : TrueMoverDiscs(movers, simulation),
                              &cloud_W);
        }
        if (run_options.on_lidar_frame) {
          run_options.on_lidar_frame(cloud_W, state.X_WB, simulation.time());
        }
        if (mapper) {
          // the frame reaches the mapper after the modelled latency
          pending_frames.push_back({simulation.time() + scenario.navigation.mapping_latency_s,
                                    std::move(cloud_W), state.X_WB, simulation.time()});
        }
        if (run_options.max_lidar_frames > 0 &&
            summary.lidar_frames >= run_options.max_lidar_frames)
          break;
      }
    }

    while (mapper && !pending_frames.empty() &&
           pending_frames.front().ready_s <= simulation.time() + 1e-9) {
      const PendingFrame& pending = pending_frames.front();
      const auto map_start = std::chrono::steady_clock::now();
      map_updates.push_back(mapper->Update(pending.cloud_W, pending.X_WB, pending.scan_time_s));
      mapping_ms.push_back(MillisecondsSince(map_start));
      times.Add("mapping", mapping_ms.back());
      pending_frames.pop_front();
      navigation_map = &mapper->map();
      map_changed = true;
      if (truth_W) {
        last_mapping_error =
            CompareWithTruth(mapper->map(), *truth_W, mapping::layers::kTraversability).mean;
      }
      // the closed loop shows the map in its panel: no need to draw it as thousands of geoms
      if (video && !navigator) overlay.grids.assign(1, DrawableMap(mapper->map()));
    }

    if (video && simulation.time() >= next_frame_s - 1e-9) {
      const auto render_start = std::chrono::steady_clock::now();
      if (navigator) {
        write_navigation_frame(state, navigator->statistics().last_status);
      } else {
        renderer->Render(simulation, camera->View(state.X_WB, frame_period_s), overlay, &frame);
        video->Write(frame);
      }
      times.Add("render", MillisecondsSince(render_start));
      next_frame_s += frame_period_s;
    }

    const auto physics_start = std::chrono::steady_clock::now();
    const sim::StepStatus status = simulation.Step();
    times.Add("physics", MillisecondsSince(physics_start));
    ++summary.physics_steps;
    if (status == sim::StepStatus::kDiverged) {
      summary.outcome = Outcome::kDiverged;
      break;
    }
    state = simulation.State();
    const common::RollPitchYaw rpy = common::ToRollPitchYaw(state.X_WB.linear());
    summary.max_roll_deg = std::max(summary.max_roll_deg, std::abs(rpy.roll) * kRadToDeg);
    summary.max_pitch_deg = std::max(summary.max_pitch_deg, std::abs(rpy.pitch) * kRadToDeg);
    sum_roll2 += rpy.roll * rpy.roll;
    sum_pitch2 += rpy.pitch * rpy.pitch;
    const Eigen::Vector2d xy = state.X_WB.translation().head<2>();
    summary.distance_m += (xy - last_xy).norm();
    last_xy = xy;

    if ((step + 1) % steps_per_sample == 0) {
      const Eigen::Vector3d p = state.X_WB.translation();
      char line[512];
      std::snprintf(line, sizeof(line),
                    "%.3f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.4f,%.4f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f\n",
                    state.time_s, p.x(), p.y(), p.z(), rpy.roll, rpy.pitch, rpy.yaw,
                    state.v_WB_B.x(), state.w_WB_B.z(), command.v, command.omega,
                    state.wheel_speeds[0], state.wheel_speeds[1], state.wheel_speeds[2],
                    state.wheel_speeds[3]);
      trajectory << line;
    }
    if (common::TiltAngle(state.X_WB.linear()) > tilt_limit) {
      summary.outcome = Outcome::kRolledOver;
      break;
    }
    simulation.RobotContacts(&contacts);
    const auto collision =
        std::find_if(contacts.begin(), contacts.end(),
                     [](const sim::RobotContact& c) { return sim::IsCollision(c); });
    if (collision != contacts.end()) {
      summary.outcome = Outcome::kCollision;
      CollisionRecord record{std::string(collision->target_name),
                             collision->target == sim::ContactTarget::kMover,
                             collision->relative_speed_m_s, state.time_s};
      const Eigen::Vector2d v_robot_W = (state.X_WB.linear() * state.v_WB_B).head<2>();
      record.robot_speed_m_s = v_robot_W.norm();
      if (record.mover) {
        record.caused_by = CollisionCause(
            xy, v_robot_W, simulation.MoverPose(collision->target_index).translation().head<2>(),
            simulation.MoverVelocity(collision->target_index));
      }
      summary.collision = record;
      break;
    }
    if (navigator) {
      const double vertical_speed = (state.X_WB.linear() * state.v_WB_B).z();
      const double vertical_acceleration = (vertical_speed - previous_vertical_speed) / dt;
      previous_vertical_speed = vertical_speed;
      if (step > 0) sum_vertical_acceleration2 += vertical_acceleration * vertical_acceleration;
      const double goal_distance = (xy - scenario.goal_W).norm();
      if ((step + 1) % (5 * steps_per_sample) == 0) {
        driven_W.push_back(xy);
        if (video) {
          // the plan on the ground in the camera's view
          renders::Polyline planned;
          planned.rgba = Eigen::Vector4f(1.0f, 1.0f, 1.0f, 1.0f);
          // at most kMaxPlanSegments capsules: each is one geom for the software renderer
          const std::vector<common::TrajectoryPoint>& points = navigator->trajectory().points();
          const std::size_t stride = std::max<std::size_t>(1, points.size() / kMaxPlanSegments + 1);
          for (std::size_t i = 0; i < points.size(); i += stride) {
            const Eigen::Vector2d& p = points[i].position_W;
            planned.points_W.emplace_back(p.x(), p.y(), world.GroundHeight(p) + 0.05);
          }
          overlay.polylines.assign(1, std::move(planned));
        }
        char line[512];
        std::snprintf(line, sizeof(line),
                      "%.3f,%.4f,%.4f,%.4f,%.4f,%.4f,%.3f,%.3f,%.4f,%.3f,%.3f,%.4f,%.5f",
                      state.time_s, xy.x(), xy.y(), rpy.yaw, state.v_WB_B.x(), state.w_WB_B.z(),
                      rpy.roll * kRadToDeg, rpy.pitch * kRadToDeg, vertical_acceleration, command.v,
                      command.omega, goal_distance, last_mapping_error);
        timeseries << line;
        // wall time of each module since the previous row [ms]
        for (const char* module : kTimedModules) {
          const double total = times.Total(module);
          std::snprintf(line, sizeof(line), ",%.3f", total - module_totals_ms[module]);
          module_totals_ms[module] = total;
          timeseries << line;
        }
        timeseries << '\n';
      }
      if (goal_distance <= scenario.navigation.goal_radius_m) {
        summary.outcome = Outcome::kSuccess;
        navigation.goal_reached = true;
        navigation.time_to_goal_s = state.time_s;
        break;
      }
      if (progress_monitor->Update(state.time_s, xy)) {
        summary.outcome = Outcome::kStuck;
        break;
      }
      if (navigator->time_without_plan_s(state.time_s) >
          scenario.navigation.planning_failure_time_s) {
        summary.outcome = Outcome::kPlanningFailure;
        break;
      }
      if (step + 1 == total_steps) summary.outcome = Outcome::kTimeout;
    }
    if (progress && (step - progress_step) * dt >= 0.5) {
      progress_step = step;
      progress(static_cast<double>(step + 1) / total_steps);
    }
  }
  if (progress) progress(1.0);

  if (navigator) {
    driven_W.push_back(state.X_WB.translation().head<2>());
    if (video)
      write_navigation_frame(state, std::string("outcome: ") + OutcomeName(summary.outcome));
    const common::GridLayers& shown = navigation_map != nullptr ? *navigation_map : *truth_W;
    const double span = std::max(world.geometry.Extent().x(), world.geometry.Extent().y());
    renders::PanelOverlay panel = NavigationPanel(*navigator, driven_W, scenario.goal_W, state,
                                                  predicted_movers, Eigen::Matrix3Xf());
    renders::WritePng(output_dir + "/map_paths.png",
                      renders::DrawMapPanel(shown, shown.Layer(mapping::layers::kTraversability),
                                            world.geometry.Center(), span, 800, panel));
  }
  if (video) {
    video->Close();
    summary.video_frames = video->frames_written();
  }
  trajectory.close();
  CheckWritten(output_dir + "/trajectory.csv", !trajectory.fail());

  summary.sim_time_s = simulation.time();
  summary.wall_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  summary.real_time_factor =
      summary.wall_time_s > 0.0 ? summary.sim_time_s / summary.wall_time_s : 0.0;
  const double n = std::max(1, summary.physics_steps);
  summary.rms_roll_deg = std::sqrt(sum_roll2 / n) * kRadToDeg;
  summary.rms_pitch_deg = std::sqrt(sum_pitch2 / n) * kRadToDeg;
  summary.final_pose_W.position = state.X_WB.translation().head<2>();
  summary.final_pose_W.yaw = common::ToRollPitchYaw(state.X_WB.linear()).yaw;
  summary.final_pose_W.time_s = state.time_s;
  if (summary.lidar_frames > 0) {
    summary.lidar_points_per_frame = lidar_points / summary.lidar_frames;
    summary.lidar_ms_per_frame = 1e3 * lidar_cast_s / summary.lidar_frames;
  }
  if (tracker) summary.tracking = tracker->Metrics();
  if (navigator) {
    const planner::Navigator::Statistics& stats = navigator->statistics();
    navigation.plans = stats.plans;
    navigation.failed_plans = stats.failed_plans;
    navigation.replans_on_events = stats.replans_on_events;
    navigation.safety_stops = stats.safety_stops;
    if (tracking_error_count > 0) {
      navigation.mover_tracking_error_m = tracking_error_sum / tracking_error_count;
      navigation.perceived_mover_samples = tracking_error_count;
    }
    navigation.last_planner_status = stats.last_status;
    navigation.final_goal_distance_m =
        (state.X_WB.translation().head<2>() - scenario.goal_W).norm();
    if (navigation.optimal_path_length_m > 0.0) {
      navigation.path_length_ratio = summary.distance_m / navigation.optimal_path_length_m;
      navigation.barn_score = BarnScore(
          navigation.goal_reached, navigation.time_to_goal_s,
          navigation.optimal_path_length_m / scenario.planner.optimizer.limits.max_speed_m_s);
    }
    navigation.rms_vertical_acceleration_m_s2 =
        std::sqrt(sum_vertical_acceleration2 / std::max(1, summary.physics_steps - 1));
    summary.tracking = navigator->tracking_metrics();
    summary.navigation = navigation;
    timeseries.close();
    CheckWritten(output_dir + "/timeseries.csv", !timeseries.fail());
    summary.plots = PlotsJson(WriteRunPlots(output_dir));
  }
  summary.compute = times.ToJson();
  if (mapper && !mapping_ms.empty()) {
    summary.mapping_updates = static_cast<int>(mapping_ms.size());
    std::sort(mapping_ms.begin(), mapping_ms.end());
    summary.mapping_ms_median = mapping_ms[mapping_ms.size() / 2];
    summary.mapping_ms_max = mapping_ms.back();
    auto median_of = [&](auto field) {
      std::vector<double> values;
      for (const mapping::MapUpdateResult& update : map_updates) values.push_back(field(update));
      return common::Quantile(std::move(values), 0.5);
    };
    summary.mapping_stage_ms_median = {
        {"crop", median_of([](const auto& u) { return u.times.crop; })},
        {"features", median_of([](const auto& u) { return u.times.features; })},
        {"fit", median_of([](const auto& u) { return u.times.fit; })},
        {"predict", median_of([](const auto& u) { return u.times.predict; })},
        {"fusion", median_of([](const auto& u) { return u.times.fusion; })},
        {"smoothing", median_of([](const auto& u) { return u.times.smoothing; })}};
    summary.mapping_training_points_median = static_cast<int>(
        median_of([](const auto& u) { return static_cast<double>(u.training_points); }));
    // the final map against the ground truth on the same cells
    const common::GridLayers& map = mapper->map();
    const common::GridLayers truth =
        mapping::ComputeGroundTruth(map.geometry(), world.geometry, world.height_m,
                                    obstacle_heights(), scenario.mapping, scenario.ground_truth);
    const Eigen::MatrixXf& predicted = map.Layer(mapping::layers::kTraversability);
    const Eigen::MatrixXf& expected = truth.Layer(mapping::layers::kTraversability);
    const LayerError error = CompareLayers(predicted, expected);
    summary.mapping_known_cells = error.known_cells;
    summary.mapping_mean_error = error.mean;
    summary.mapping_error_variance = error.variance;
    renders::WritePng(output_dir + "/map.png", renders::TraversabilityImage(predicted));
    renders::WritePng(output_dir + "/map_ground_truth.png", renders::TraversabilityImage(expected));
  }
  summary.mujoco_warning_count = simulation.warning_count();
  summary.mujoco_warnings = simulation.warnings();
  return summary;
}

std::string SummaryJson(const Scenario& scenario, const RunSummary& summary) {
  nlohmann::json json;
  json["scenario"] = scenario.name;
  json["outcome"] = OutcomeName(summary.outcome);
  json["expected_outcome"] = OutcomeName(scenario.expected_outcome);
  json["terrain"] = {{"type", sim::TerrainTypeName(scenario.terrain.type)},
                     {"seed", scenario.terrain.seed}};
  json["provenance"] = Provenance(ResolvedScenarioYaml(scenario));
  json["sim_time_s"] = summary.sim_time_s;
  json["wall_time_s"] = summary.wall_time_s;
  json["real_time_factor"] = summary.real_time_factor;
  json["distance_m"] = summary.distance_m;
  json["max_roll_deg"] = summary.max_roll_deg;
  json["max_pitch_deg"] = summary.max_pitch_deg;
  json["rms_roll_deg"] = summary.rms_roll_deg;
  json["rms_pitch_deg"] = summary.rms_pitch_deg;
  json["final_pose"] = {{"x", summary.final_pose_W.position.x()},
                        {"y", summary.final_pose_W.position.y()},
                        {"yaw", summary.final_pose_W.yaw}};
  json["physics_steps"] = summary.physics_steps;
  json["mujoco_warning_count"] = summary.mujoco_warning_count;
  json["mujoco_warnings"] = summary.mujoco_warnings;
  json["video"] = summary.video_frames > 0 ? nlohmann::json("video.mp4") : nlohmann::json(nullptr);
  json["video_frames"] = summary.video_frames;
  json["lidar_frames"] = summary.lidar_frames;
  json["lidar_points_per_frame"] = summary.lidar_points_per_frame;
  json["lidar_ms_per_frame"] = summary.lidar_ms_per_frame;
  if (summary.mapping_updates > 0) {
    json["mapping"] = {{"method", MapperMethodName(scenario.mapper)},
                       {"updates", summary.mapping_updates},
                       {"update_ms_median", summary.mapping_ms_median},
                       {"update_ms_max", summary.mapping_ms_max},
                       {"stage_ms_median", summary.mapping_stage_ms_median},
                       {"training_points_median", summary.mapping_training_points_median},
                       {"known_cells", summary.mapping_known_cells},
                       {"mean_error", summary.mapping_mean_error},
                       {"error_variance", summary.mapping_error_variance}};
  }
  if (summary.navigation) {
    const NavigationMetrics& n = *summary.navigation;
    json["navigation"] = {{"goal", {scenario.goal_W.x(), scenario.goal_W.y()}},
                          {"goal_reached", n.goal_reached},
                          {"time_to_goal_s", n.time_to_goal_s},
                          {"final_goal_distance_m", n.final_goal_distance_m},
                          {"path_length_m", summary.distance_m},
                          {"optimal_path_length_m", n.optimal_path_length_m},
                          {"path_length_ratio", n.path_length_ratio},
                          {"barn_score", n.barn_score},
                          {"rms_vertical_acceleration_m_s2", n.rms_vertical_acceleration_m_s2},
                          {"plans", n.plans},
                          {"failed_plans", n.failed_plans},
                          {"replans_on_events", n.replans_on_events},
                          {"safety_stops", n.safety_stops},
                          {"last_planner_status", n.last_planner_status},
                          {"mover_tracking_error_m", n.mover_tracking_error_m},
                          {"perceived_mover_samples", n.perceived_mover_samples},
                          {"false_mover_samples", n.false_mover_samples},
                          {"near_misses", n.near_misses},
                          {"min_mover_clearance_m", std::isfinite(n.min_mover_clearance_m)
                                                        ? nlohmann::json(n.min_mover_clearance_m)
                                                        : nlohmann::json(nullptr)}};
  }
  if (summary.collision) {
    json["collision"] = {{"with", summary.collision->target},
                         {"mover", summary.collision->mover},
                         {"relative_speed_m_s", summary.collision->relative_speed_m_s},
                         {"robot_speed_m_s", summary.collision->robot_speed_m_s},
                         {"caused_by", summary.collision->caused_by},
                         {"time_s", summary.collision->time_s}};
  }
  json["compute"] = summary.compute;
  if (summary.navigation) json["plots"] = summary.plots;
  if (summary.tracking) {
    const controller::TrackingMetrics& m = *summary.tracking;
    json["tracking"] = {
        {"rms_lateral_error_m", m.rms_lateral_error_m},
        {"max_lateral_error_m", m.max_lateral_error_m},
        {"rms_heading_error_rad", m.rms_heading_error_rad},
        {"max_heading_error_rad", m.max_heading_error_rad},
        {"rms_speed_error_m_s", m.rms_speed_error_m_s},
        {"max_speed_error_m_s", m.max_speed_error_m_s},
        {"rms_acceleration_command_m_s2", m.rms_acceleration_command_m_s2},
        {"rms_yaw_acceleration_command_rad_s2", m.rms_yaw_acceleration_command_rad_s2},
        {"solve_time_median_ms", m.solve_time_median_ms},
        {"solve_time_p99_ms", m.solve_time_p99_ms},
        {"solve_time_max_ms", m.solve_time_max_ms},
        {"iterations_mean", m.iterations_mean},
        {"solves", m.solves},
        {"failures", m.failures},
        {"iteration_limits", m.iteration_limits}};
  }
  return json.dump(2) + "\n";
}

}  // namespace trav::scenarios
