#include "scenarios/run/scenario_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "common/enum_names.h"
#include "common/input_error.h"
#include "common/statistics.h"
#include "mapping/ground_truth.h"
#include "mapping/physical_truth.h"
#include "planner/astar.h"
#include "renders/image.h"
#include "scenarios/run/mcap_recorder.h"
#include "scenarios/run/output_folder.h"
#include "scenarios/run/plots.h"
#include "scenarios/run/provenance.h"
#include "scenarios/run/recorders.h"
#include "scenarios/run/run_metrics.h"
#include "scenarios/run/video_recorder.h"
#include "sim/simulation.h"
#include "sim/terrain_geometry.h"
#include "sim/world_builder.h"

namespace trav::scenarios {
namespace {

// The mapping part of a summary: updates, their times and stages, and the final map's error
// against the ground truth on its own cells (returned).
common::GridLayers SummarizeMapping(const ClosedLoop& loop, MappingMetrics* metrics) {
  metrics->method = loop.scenario().mapper;
  std::vector<double> mapping_ms = loop.mapping_ms();
  metrics->updates = static_cast<int>(mapping_ms.size());
  std::sort(mapping_ms.begin(), mapping_ms.end());
  metrics->update_ms_median = mapping_ms[mapping_ms.size() / 2];
  metrics->update_ms_max = mapping_ms.back();
  auto median_of = [&](auto field) {
    std::vector<double> values;
    for (const mapping::MapUpdateResult& update : loop.map_updates()) {
      values.push_back(field(update));
    }
    return common::Quantile(std::move(values), 0.5);
  };
  metrics->stage_ms_median = {
      {"crop", median_of([](const auto& u) { return u.times.crop; })},
      {"features", median_of([](const auto& u) { return u.times.features; })},
      {"fit", median_of([](const auto& u) { return u.times.fit; })},
      {"predict", median_of([](const auto& u) { return u.times.predict; })},
      {"fusion", median_of([](const auto& u) { return u.times.fusion; })},
      {"smoothing", median_of([](const auto& u) { return u.times.smoothing; })}};
  metrics->training_points_median = static_cast<int>(
      median_of([](const auto& u) { return static_cast<double>(u.training_points); }));
  // the final map against the ground truth on the same cells
  const common::GridLayers& map = *loop.map();
  const sim::TerrainWorld& world = loop.world();
  common::GridLayers truth = mapping::ComputeGroundTruth(
      map.geometry(), world.geometry, world.height_m, loop.obstacle_heights(),
      loop.scenario().mapping, loop.scenario().ground_truth);
  const LayerError error = CompareLayers(map.Layer(mapping::layers::kTraversability),
                                         truth.Layer(mapping::layers::kTraversability));
  metrics->known_cells = error.known_cells;
  metrics->mean_error = error.mean;
  metrics->error_variance = error.variance;
  return truth;
}

// The navigation part of a summary.
NavigationMetrics SummarizeNavigation(const ClosedLoop& loop, const RunSummary& summary,
                                      const GoalCondition& goal, const MoverEncounters& movers,
                                      const MotionStatistics& motion) {
  const Scenario& scenario = loop.scenario();
  NavigationMetrics navigation;
  navigation.goal_reached = summary.outcome == Outcome::kSuccess;
  navigation.time_to_goal_s = goal.time_to_goal_s();
  // with the footprint the navigator read from the robot file
  Scenario resolved = scenario;
  resolved.planner = loop.navigator()->planner_config();
  navigation.optimal_path_length_m = OptimalPathLength(resolved, *loop.truth());
  const planner::Navigator::Statistics& stats = loop.navigator()->statistics();
  navigation.plans = stats.plans;
  navigation.failed_plans = stats.failed_plans;
  navigation.replans_on_events = stats.replans_on_events;
  navigation.safety_stops = stats.safety_stops;
  navigation.fallbacks = stats.fallbacks;
  navigation.give_ways = stats.give_ways;
  navigation.back_offs = stats.back_offs;
  navigation.step_climbs = stats.step_climbs;
  navigation.mover_tracking_error_m = movers.tracking_error_m();
  navigation.perceived_mover_samples = movers.perceived_samples();
  navigation.false_mover_samples = movers.false_mover_samples();
  navigation.min_mover_clearance_m = movers.min_clearance_m();
  navigation.near_misses = movers.near_misses();
  navigation.last_planner_status = stats.last_status;
  navigation.final_goal_distance_m =
      (loop.state().X_WB.translation().head<2>() - scenario.goal_W).norm();
  navigation.goal_W = scenario.goal_W;
  navigation.path_length_m = summary.distance_m;
  if (navigation.optimal_path_length_m > 0.0) {
    navigation.path_length_ratio = summary.distance_m / navigation.optimal_path_length_m;
    navigation.barn_score = BarnScore(
        navigation.goal_reached, navigation.time_to_goal_s,
        navigation.optimal_path_length_m / scenario.planner.optimizer.limits.max_speed_m_s);
  }
  navigation.rms_vertical_acceleration_m_s2 =
      motion.rms_vertical_acceleration_m_s2(summary.physics_steps);
  return navigation;
}

}  // namespace

std::vector<sim::MovingObstacle> ScenarioMovers(const Scenario& scenario,
                                                const sim::TerrainWorld& world,
                                                const Eigen::MatrixXf& obstacle_heights) {
  std::vector<sim::MovingObstacle> movers = scenario.movers;
  if (scenario.traffic.count == 0) return movers;
  // free: no obstacle surface on the world's height grid within the disc
  const common::GridGeometry& g = world.geometry;
  // off the terrain: nothing to walk into
  auto free = [&](const Eigen::Vector2d& centre_W, double radius_m) {
    return !common::AnyCellWithin(g, centre_W, radius_m,
                                  [&](int ix, int iy) { return obstacle_heights(ix, iy) > 0.0f; });
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

sim::ObstacleRaster RestingObstacles(const sim::TerrainWorld& world) {
  return sim::ObstacleBandRaster(world, mapping::RestingBody{}.height_m,
                                 mapping::kObstacleOutlineResolution_m);
}

common::GridLayers WorldPhysicalTruth(const common::GridGeometry& map_geometry,
                                      const sim::TerrainWorld& world,
                                      const mapping::GroundTruthConfig& config,
                                      const std::vector<Eigen::Vector2i>* cells) {
  const sim::ObstacleRaster obstacles = RestingObstacles(world);
  const mapping::RestingSurface surface{world.geometry, world.height_m, obstacles.geometry,
                                        obstacles.top_m};
  return cells
             ? mapping::ComputePhysicalTruth(map_geometry, *cells, surface, mapping::RestingBody{},
                                             config)
             : mapping::ComputePhysicalTruth(map_geometry, surface, mapping::RestingBody{}, config);
}

common::GridLayers ScenarioGroundTruth(const Scenario& scenario) {
  const sim::TerrainWorld world =
      sim::GenerateTerrain(scenario.terrain, {scenario.start_W.position, scenario.goal_W});
  return WorldGroundTruth(scenario, world, sim::ObstacleHeightGrid(world));
}

double OptimalPathLength(const Scenario& scenario, const common::GridLayers& truth) {
  const planner::GridPlanner search(truth, scenario.planner.SearchConfig());
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

std::optional<PreparedWorld> RoutableWorld(const Scenario& scenario) {
  PreparedWorld prepared;
  prepared.world =
      sim::GenerateTerrain(scenario.terrain, {scenario.start_W.position, scenario.goal_W});
  prepared.obstacle_heights = sim::ObstacleHeightGrid(prepared.world);
  common::GridLayers obstacles(prepared.world.geometry, {mapping::layers::kTraversability});
  obstacles.Layer(mapping::layers::kTraversability) =
      (prepared.obstacle_heights.array() > scenario.ground_truth.clearance_m).cast<float>();
  const planner::GridPlanner quick(obstacles, scenario.planner.SearchConfig());
  if (quick.Plan(scenario.start_W.position, scenario.goal_W).status !=
      planner::PlanStatus::kFound) {
    return std::nullopt;
  }
  prepared.truth_W = WorldGroundTruth(scenario, prepared.world, prepared.obstacle_heights);
  if (OptimalPathLength(scenario, prepared.truth_W) <= 0.0) return std::nullopt;
  return prepared;
}

std::string RobotModelPath(const Scenario& scenario, const std::string& models_dir) {
  const std::filesystem::path model(scenario.robot_model);
  return model.is_absolute() ? model.string()
                             : (std::filesystem::path(models_dir) / model).string();
}

std::string RobotUrdfOf(const std::string& robot_model_path) {
  return sim::RobotUrdf(robot_model_path);
}

std::string CheckedRobotModelPath(const Scenario& scenario, const std::string& models_dir) {
  const std::string model = RobotModelPath(scenario, models_dir);
  common::ValidateAt("robot.model", [&] { sim::ValidateRobotModel(model, scenario.imu.enabled); });
  return model;
}

RunSummary RunLoop(ClosedLoop* loop, const std::vector<LoopObserver*>& observers,
                   const ProgressCallback& progress,
                   std::optional<common::GridLayers>* final_map_truth) {
  const Scenario& scenario = loop->scenario();
  const bool navigate = loop->navigator() != nullptr;
  MotionStatistics motion(loop->state().X_WB.translation().head<2>());
  LocalizationError localization;
  if (scenario.pose_noise.active()) loop->AddObserver(&localization);
  MoverEncounters movers(scenario.planner.optimizer.robot_radius_m,
                         scenario.navigation.near_miss_clearance_m);
  loop->AddObserver(&motion);
  if (navigate) loop->AddObserver(&movers);
  for (LoopObserver* observer : observers) loop->AddObserver(observer);
  loop->AddEndCondition(std::make_unique<RolloverCondition>(scenario.rollover_limit_deg));
  auto collision = std::make_unique<CollisionCondition>();
  const CollisionCondition& collision_record = *collision;
  loop->AddEndCondition(std::move(collision));
  auto goal = std::make_unique<GoalCondition>(scenario.goal_W, scenario.navigation.goal_radius_m);
  const GoalCondition& goal_record = *goal;
  const PlanningFailureCondition* planning_failure_record = nullptr;
  if (navigate) {
    loop->AddEndCondition(std::move(goal));
    loop->AddEndCondition(std::make_unique<StuckCondition>(scenario.navigation.stuck_time_s,
                                                           scenario.navigation.stuck_distance_m));
    auto planning_failure = std::make_unique<PlanningFailureCondition>(
        scenario.navigation.planning_failure_time_s, scenario.navigation.livelock_time_s,
        scenario.navigation.livelock_radius_m);
    planning_failure_record = planning_failure.get();
    loop->AddEndCondition(std::move(planning_failure));
    loop->AddEndCondition(std::make_unique<TimeoutCondition>());
  }

  RunSummary summary;
  summary.outcome = loop->Run(progress);
  summary.sim_time_s = loop->simulation().time();
  summary.wall_time_s = loop->wall_time_s();
  summary.real_time_factor =
      summary.wall_time_s > 0.0 ? summary.sim_time_s / summary.wall_time_s : 0.0;
  summary.physics_steps = loop->physics_steps();
  summary.distance_m = motion.distance_m();
  summary.max_roll_deg = motion.max_roll_deg();
  summary.max_pitch_deg = motion.max_pitch_deg();
  summary.rms_roll_deg = motion.rms_roll_deg(summary.physics_steps);
  summary.rms_pitch_deg = motion.rms_pitch_deg(summary.physics_steps);
  const common::RobotState& state = loop->state();
  summary.final_pose_W.position = state.X_WB.translation().head<2>();
  summary.final_pose_W.yaw = common::ToRollPitchYaw(state.X_WB.linear()).yaw;
  summary.final_pose_W.time_s = state.time_s;
  summary.lidar_frames = loop->lidar_frames();
  if (summary.lidar_frames > 0) {
    summary.lidar_points_per_frame = loop->lidar_points() / summary.lidar_frames;
    summary.lidar_ms_per_frame = 1e3 * loop->lidar_cast_s() / summary.lidar_frames;
  }
  if (loop->tracker() != nullptr) summary.tracking = loop->tracker()->Metrics();
  if (navigate) {
    summary.tracking = loop->navigator()->tracking_metrics();
    summary.navigation = SummarizeNavigation(*loop, summary, goal_record, movers, motion);
    if (summary.outcome == Outcome::kPlanningFailure) {
      summary.navigation->planning_failure_cause = planning_failure_record->cause();
    }
  }
  summary.collision = collision_record.record();
  if (scenario.pose_noise.active()) {
    summary.localization = localization.Metrics(loop->estimate(), loop->state());
    summary.localization->method = scenario.pose_noise.method;
  }
  summary.compute = loop->times().Summary();
  if (loop->map() != nullptr) {
    common::GridLayers truth = SummarizeMapping(*loop, &summary.mapping.emplace());
    if (final_map_truth != nullptr) *final_map_truth = std::move(truth);
  }
  summary.mujoco_warning_count = loop->simulation().warning_count();
  summary.mujoco_warnings = loop->simulation().warnings();
  return summary;
}

RunSummary RunScenario(const Scenario& scenario, const std::string& robot_model_path,
                       const std::string& output_dir, const RunOptions& options,
                       const ProgressCallback& progress) {
  ClosedLoop loop(scenario, {robot_model_path, options.max_lidar_frames, options.mapping_thread,
                             options.lidar_thread});
  // the simulated world as a file MuJoCo's viewer opens (simulate world.xml)
  sim::ExportWorld(loop.world(), loop.world_options(), loop.movers(), output_dir);
  const bool navigate = loop.navigator() != nullptr;
  // the files of a run, each written by its observer; the driven path goes first, as the video
  // and the map of paths draw it
  std::vector<LoopObserver*> observers;
  DrivenPath driven(scenario.start_W.position);
  if (navigate) observers.push_back(&driven);
  TrajectoryRecorder trajectory(output_dir);
  observers.push_back(&trajectory);
  std::optional<ImuRecorder> imu;
  if (loop.imu() != nullptr) observers.push_back(&imu.emplace(output_dir));
  std::optional<TimeSeriesRecorder> timeseries;
  if (navigate) observers.push_back(&timeseries.emplace(output_dir));
  std::optional<CloudRecorder> clouds;
  if (options.record_clouds && scenario.lidar.enabled) {
    observers.push_back(&clouds.emplace(output_dir));
  }
  std::optional<VideoRecorder> video;
  if (scenario.video.enabled) observers.push_back(&video.emplace(&loop, output_dir, &driven));
  std::optional<McapRecorder> mcap;
  if (scenario.mcap) observers.push_back(&mcap.emplace(loop, output_dir));
  std::optional<MapPathsWriter> map_paths;
  if (navigate) observers.push_back(&map_paths.emplace(output_dir, &driven));

  std::optional<common::GridLayers> final_map_truth;
  RunSummary summary = RunLoop(&loop, observers, progress, &final_map_truth);
  if (video) summary.video_frames = video->frames_written();
  summary.mcap = mcap.has_value();
  if (navigate) summary.plots = PlotsJson(WriteRunPlots(output_dir));
  if (final_map_truth) {
    renders::WritePng(
        output_dir + "/map.png",
        renders::TraversabilityImage(loop.map()->Layer(mapping::layers::kTraversability)));
    renders::WritePng(
        output_dir + "/map_ground_truth.png",
        renders::TraversabilityImage(final_map_truth->Layer(mapping::layers::kTraversability)));
  }
  return summary;
}

namespace {

// {"wider_margin": n, "follow_path": n, ...}: every planner::Fallback but kNone, by its name with
// '_' for '-'.
nlohmann::json FallbackCounts(const std::array<int, planner::kFallbackNames.size()>& counts) {
  nlohmann::json json = nlohmann::json::object();
  for (const auto& [fallback, name] : planner::kFallbackNames) {
    if (fallback == planner::Fallback::kNone) continue;
    std::string key(name);
    std::replace(key.begin(), key.end(), '-', '_');
    json[key] = counts[static_cast<std::size_t>(fallback)];
  }
  return json;
}

}  // namespace

void to_json(nlohmann::json& json, const NavigationMetrics& n) {
  json = {{"goal_reached", n.goal_reached},
          {"time_to_goal_s", n.time_to_goal_s},
          {"final_goal_distance_m", n.final_goal_distance_m},
          {"optimal_path_length_m", n.optimal_path_length_m},
          {"path_length_ratio", n.path_length_ratio},
          {"barn_score", n.barn_score},
          {"rms_vertical_acceleration_m_s2", n.rms_vertical_acceleration_m_s2},
          {"plans", n.plans},
          {"failed_plans", n.failed_plans},
          {"replans_on_events", n.replans_on_events},
          {"safety_stops", n.safety_stops},
          {"fallbacks", FallbackCounts(n.fallbacks)},
          {"give_ways", n.give_ways},
          {"back_offs", n.back_offs},
          {"step_climbs", n.step_climbs},
          {"last_planner_status", n.last_planner_status},
          {"planning_failure_cause", n.planning_failure_cause},
          {"mover_tracking_error_m", n.mover_tracking_error_m},
          {"perceived_mover_samples", n.perceived_mover_samples},
          {"false_mover_samples", n.false_mover_samples},
          {"near_misses", n.near_misses},
          {"min_mover_clearance_m", std::isfinite(n.min_mover_clearance_m)
                                        ? nlohmann::json(n.min_mover_clearance_m)
                                        : nlohmann::json(nullptr)},
          {"goal", {n.goal_W.x(), n.goal_W.y()}},
          {"path_length_m", n.path_length_m}};
}

void to_json(nlohmann::json& json, const MappingMetrics& m) {
  json = {{"method", m.method},
          {"updates", m.updates},
          {"update_ms_median", m.update_ms_median},
          {"update_ms_max", m.update_ms_max},
          {"stage_ms_median", m.stage_ms_median},
          {"training_points_median", m.training_points_median},
          {"known_cells", m.known_cells},
          {"mean_error", m.mean_error},
          {"error_variance", m.error_variance}};
}

void to_json(nlohmann::json& json, const LocalizationMetrics& m) {
  json = {{"method", common::NameOf(m.method)},
          {"final_position_error_m", m.final_position_error_m},
          {"final_z_error_m", m.final_z_error_m},
          {"final_yaw_error_deg", m.final_yaw_error_deg},
          {"max_position_error_m", m.max_position_error_m},
          {"relative_error_10m_m", m.relative_error_10m_m},
          {"relative_yaw_error_10m_deg", m.relative_yaw_error_10m_deg},
          {"relative_error_stretches", m.relative_error_stretches}};
}

void to_json(nlohmann::json& json, const CollisionRecord& c) {
  json = {{"with", c.target},
          {"mover", c.mover},
          {"relative_speed_m_s", c.relative_speed_m_s},
          {"robot_speed_m_s", c.robot_speed_m_s},
          {"caused_by", c.caused_by},
          {"time_s", c.time_s}};
}

void to_json(nlohmann::json& json, const RunSummary& s) {
  json = {{"outcome", common::NameOf(s.outcome)},
          {"sim_time_s", s.sim_time_s},
          {"wall_time_s", s.wall_time_s},
          {"real_time_factor", s.real_time_factor},
          {"distance_m", s.distance_m},
          {"max_roll_deg", s.max_roll_deg},
          {"max_pitch_deg", s.max_pitch_deg},
          {"rms_roll_deg", s.rms_roll_deg},
          {"rms_pitch_deg", s.rms_pitch_deg},
          {"final_pose",
           {{"x", s.final_pose_W.position.x()},
            {"y", s.final_pose_W.position.y()},
            {"yaw", s.final_pose_W.yaw}}},
          {"physics_steps", s.physics_steps},
          {"mujoco_warning_count", s.mujoco_warning_count},
          {"mujoco_warnings", s.mujoco_warnings},
          {"video", s.video_frames > 0 ? nlohmann::json("video.mp4") : nlohmann::json(nullptr)},
          {"video_frames", s.video_frames},
          {"mcap", s.mcap ? nlohmann::json(kMcapFileName) : nlohmann::json(nullptr)},
          {"lidar_frames", s.lidar_frames},
          {"lidar_points_per_frame", s.lidar_points_per_frame},
          {"lidar_ms_per_frame", s.lidar_ms_per_frame},
          {"compute", s.compute}};
  if (s.mapping) json["mapping"] = *s.mapping;
  if (s.navigation) {
    json["navigation"] = *s.navigation;
    json["plots"] = s.plots;
  }
  if (s.collision) json["collision"] = *s.collision;
  if (s.tracking) json["tracking"] = *s.tracking;
  if (s.localization) json["localization"] = *s.localization;
}

void to_json(nlohmann::json& json, const SummaryFile& file) {
  json = file.summary;
  json["scenario"] = file.scenario;
  json["expected_outcome"] = common::NameOf(file.expected_outcome);
  json["terrain"] = {{"type", common::NameOf(file.terrain_type)}, {"seed", file.terrain_seed}};
  json["provenance"] = file.provenance;
}

std::string SummaryJson(const Scenario& scenario, const RunSummary& summary) {
  const SummaryFile file{scenario.name,
                         scenario.expected_outcome,
                         scenario.terrain.type,
                         scenario.terrain.seed,
                         Provenance(ResolvedScenarioYaml(scenario)),
                         summary};
  return nlohmann::json(file).dump(2) + "\n";
}

SummaryFile SummaryWithEverySection() {
  SummaryFile file;
  RunSummary& summary = file.summary;
  summary.tracking.emplace();
  summary.mapping.emplace();
  summary.navigation.emplace().min_mover_clearance_m = 0.0;  // finite: a number
  summary.collision.emplace();
  summary.localization.emplace();
  for (const char* module : kTimedModules) summary.compute[module] = ModuleTime{};
  return file;
}

}  // namespace trav::scenarios

namespace trav::controller {

void to_json(nlohmann::json& json, const TrackingMetrics& m) {
  json = {{"rms_lateral_error_m", m.rms_lateral_error_m},
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

}  // namespace trav::controller
