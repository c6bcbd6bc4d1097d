#include "planner/navigation_planner.h"

#include <cmath>
#include <optional>
#include <utility>

#include "common/input_error.h"
#include "common/stopwatch.h"
#include "planner/cost_field.h"
#include "planner/pose_search.h"

namespace trav::planner {
namespace {

// A robot heading this close to its path's first segment [rad] is not turned toward it: the
// optimiser failed on an aligned start, and the next fallback (backing out) is tried instead.
constexpr double kAlignedYaw_rad = 0.2;

// The centre of the unblocked cell nearest to p_W within `radius_m`, if any: a robot standing in
// the inflation of lethal cells (after a swerve, or when cells turn lethal around it) searches
// from there.
std::optional<Eigen::Vector2d> NearestFreeCell(const SearchCostMap& costs,
                                               const Eigen::Vector2d& p_W, double radius_m) {
  const common::GridGeometry& g = costs.geometry();
  const std::optional<Eigen::Vector2i> centre = g.CellIndex(p_W);
  if (!centre) return std::nullopt;
  const int r = static_cast<int>(std::ceil(radius_m / g.resolution_m));
  std::optional<Eigen::Vector2d> best;
  double best_distance = radius_m;
  for (int dx = -r; dx <= r; ++dx) {
    for (int dy = -r; dy <= r; ++dy) {
      const int ix = centre->x() + dx, iy = centre->y() + dy;
      if (!g.Contains(ix, iy) || !std::isfinite(costs.cost(ix, iy))) continue;
      const double d = (g.CellCenter(ix, iy) - p_W).norm();
      if (d <= best_distance) {
        best_distance = d;
        best = g.CellCenter(ix, iy);
      }
    }
  }
  return best;
}

// The optimiser's request from `start` along `guide_W` to its last point, among `obstacles`.
TrajectoryRequest RequestAlong(const common::TrajectoryPoint& start,
                               const std::vector<Eigen::Vector2d>& guide_W,
                               const std::vector<MovingObstacle>& obstacles) {
  TrajectoryRequest request;
  request.start = start;
  request.goal_W = guide_W.back();
  request.guide_W = guide_W;
  request.obstacles = obstacles;
  return request;
}

// The point at arc length `length_m` along the polyline `points_W` (its end if it is shorter).
Eigen::Vector2d PointAlong(const std::vector<Eigen::Vector2d>& points_W, double length_m) {
  for (std::size_t i = 1; i < points_W.size(); ++i) {
    const double segment_m = (points_W[i] - points_W[i - 1]).norm();
    if (segment_m >= length_m) {
      return points_W[i - 1] + (points_W[i] - points_W[i - 1]) * (length_m / segment_m);
    }
    length_m -= segment_m;
  }
  return points_W.back();
}

// A pose-search way is followed without periodic replans over at most its first this many metres
// [m]: through the gap at hand (a robot length and a half), not its whole reach, which in clutter
// is narrow throughout (BARN: 18 s of creeping, with the map growing round the way meanwhile).
constexpr double kMaxCommitLength_m = 1.0;

// The time of the last sample of `way`, within its first kMaxCommitLength_m of driving, where the
// disc of `free_radius_m` round the base reaches lethal cells, or its start time if there is none.
double NarrowsEnd(const CostField& field, const common::Trajectory& way, double free_radius_m) {
  double end_s = way.start_time();
  double driven_m = 0.0;
  const std::vector<common::TrajectoryPoint>& points = way.points();
  for (std::size_t i = 0; i < points.size() && driven_m <= kMaxCommitLength_m; ++i) {
    if (i > 0) driven_m += (points[i].position_W - points[i - 1].position_W).norm();
    if (field.Distance(points[i].position_W).value < free_radius_m) end_s = points[i].t_s;
  }
  return end_s;
}

}  // namespace

void ValidateNavigationPlannerConfig(const NavigationPlannerConfig& c) {
  using common::RequireValue;
  const CostMapConfig& s = c.search;
  RequireValue(s.cost_weight >= 0.0, "search.cost_weight", s.cost_weight, "must be >= 0");
  RequireValue(s.lethal_threshold > 0.0 && s.lethal_threshold <= 1.0, "search.lethal_threshold",
               s.lethal_threshold, "must be in (0, 1]");
  RequireValue(s.band_cost >= 0.0 && s.band_cost <= 1.0, "search.band_cost", s.band_cost,
               "must be in [0, 1]");
  RequireValue(s.unknown_cost >= 0.0 && s.unknown_cost <= 1.0, "search.unknown_cost",
               s.unknown_cost, "must be in [0, 1]");
  RequireValue(c.substitute_goal_reach_m > 0.0, "search.substitute_goal_reach",
               c.substitute_goal_reach_m, "must be > 0");
  RequireValue(c.simplify_tolerance >= 0.0, "search.simplify_tolerance", c.simplify_tolerance,
               "must be >= 0");
  const TerrainSpeedConfig& v = s.speed;
  RequireValue(v.unknown_m_s > 0.0, "speed.unknown", v.unknown_m_s, "must be > 0");
  RequireValue(v.rough_m_s > 0.0, "speed.rough", v.rough_m_s, "must be > 0");
  RequireValue(v.smooth_m >= 0.0, "speed.smooth_roughness", v.smooth_m, "must be >= 0");
  RequireValue(v.rough_m > v.smooth_m, "speed.rough_roughness", v.rough_m,
               "must be > speed.smooth_roughness");
  RequireValue(s.slope.max_pitch_deg > 0.0 && s.slope.max_pitch_deg < 90.0, "slope.max_pitch",
               s.slope.max_pitch_deg, "must be in (0, 90)");
  RequireValue(s.slope.max_roll_deg > 0.0 && s.slope.max_roll_deg < 90.0, "slope.max_roll",
               s.slope.max_roll_deg, "must be in (0, 90)");
  RequireValue(s.steps.max_angle_deg > 0.0 && s.steps.max_angle_deg <= 90.0, "steps.max_angle",
               s.steps.max_angle_deg, "must be in (0, 90]");
  RequireValue(s.steps.low_height_m >= 0.0, "steps.low_height", s.steps.low_height_m,
               "must be >= 0");
  RequireValue(s.steps.full_height_m > s.steps.low_height_m, "steps.full_height",
               s.steps.full_height_m, "must be > steps.low_height");
  common::ValidateAt("optimizer", [&] { ValidateTrajectoryOptimizerConfig(c.OptimizerConfig()); });
  common::ValidateAt("fallback", [&] { ValidateFallbackConfig(c.fallback); });
}

CostMapConfig NavigationPlannerConfig::SearchConfig() const {
  CostMapConfig resolved = search;
  resolved.inflation_radius_m = footprint.InscribedRadius() + optimizer.min_clearance_m;
  resolved.band_radius_m = footprint.CircumscribedRadius() + optimizer.clearance_m;
  resolved.speed.open_m_s = optimizer.limits.max_speed_m_s;
  resolved.speed.reach_m = footprint.CircumscribedRadius();
  resolved.steps.reach_m = footprint.CircumscribedRadius();
  return resolved;
}

TrajectoryOptimizerConfig NavigationPlannerConfig::OptimizerConfig() const {
  TrajectoryOptimizerConfig resolved = optimizer;
  resolved.footprint = footprint;
  return resolved;
}

GridPath AStarSearch(const SearchCostMap& costs, const Eigen::Vector2d& start_W,
                     const Eigen::Vector2d& goal_W) {
  return GridPlanner(costs).Plan(start_W, goal_W);
}

NavigationPlanner::NavigationPlanner(const NavigationPlannerConfig& config, PathSearch search)
    : config_(config), search_(std::move(search)), optimizer_(config.OptimizerConfig()) {
  ValidateNavigationPlannerConfig(config_);
}

NavigationPlan NavigationPlanner::Plan(const common::GridLayers& map,
                                       const common::TrajectoryPoint& start,
                                       const Eigen::Vector2d& goal_W,
                                       const std::vector<MovingObstacle>& obstacles,
                                       const common::Trajectory* followed) {
  return Plan(CostMap(map, config_.SearchConfig(), Remember(map)), start, goal_W, obstacles,
              followed);
}

std::shared_ptr<const ObstacleMemory> NavigationPlanner::Remember(const common::GridLayers& map) {
  const CostMapConfig search = config_.SearchConfig();
  const Eigen::MatrixXf& layer = map.Layer(search.cost_layer);
  if (!search.operating_area_W) return nullptr;
  if (!memory_ || !memory_->SharesLattice(map.geometry())) {
    memory_ = std::make_shared<ObstacleMemory>(*search.operating_area_W, map.geometry());
  } else if (memory_.use_count() > 1) {
    // a CostMap still holds the memory given before: it keeps that one, this is a copy
    memory_ = std::make_shared<ObstacleMemory>(*memory_);
  }
  memory_->Record(map.geometry(), layer, search);
  return memory_;
}

NavigationPlan NavigationPlanner::Plan(const CostMap& costs, const common::TrajectoryPoint& start,
                                       const Eigen::Vector2d& goal_W,
                                       const std::vector<MovingObstacle>& obstacles,
                                       const common::Trajectory* followed) {
  NavigationPlan plan;
  const common::Stopwatch search_start;
  const GridPlanner search(costs.search());
  Eigen::Vector2d search_start_W = start.position_W;
  plan.path = search_(search.costs(), search_start_W, goal_W);
  if (plan.path.status == PlanStatus::kStartBlocked) {
    const std::optional<Eigen::Vector2d> free = NearestFreeCell(
        search.costs(), start.position_W,
        costs.config().inflation_radius_m + 2.0 * search.costs().geometry().resolution_m);
    if (free) {
      search_start_W = *free;
      plan.path = search_(search.costs(), search_start_W, goal_W);
    }
  }
  // toward a goal the map cannot reach yet, keep heading for the substitute chosen before while it
  // is reachable and not close: a new nearest cell every replan makes the robot dither between
  // ways round what it has not seen
  if (plan.path.status == PlanStatus::kGoalMoved && substitute_goal_W_ &&
      (*substitute_goal_W_ - start.position_W).norm() > config_.substitute_goal_reach_m) {
    GridPath committed = search_(search.costs(), search_start_W, *substitute_goal_W_);
    if (committed.status == PlanStatus::kFound) {
      committed.status = PlanStatus::kGoalMoved;
      plan.path = std::move(committed);
    }
  }
  if (plan.path.status == PlanStatus::kGoalMoved) {
    substitute_goal_W_ = plan.path.goal_W;
  } else {
    substitute_goal_W_.reset();
  }
  if (plan.path.status == PlanStatus::kFound || plan.path.status == PlanStatus::kGoalMoved) {
    plan.waypoints_W = search.Simplify(plan.path.points_W, config_.simplify_tolerance);
  }
  plan.search_time_s = search_start.ElapsedSeconds();
  if (plan.waypoints_W.empty()) {
    plan.status = NavigationStatus::kNoPath;
    return plan;
  }
  // the path runs between cell centres: start exactly at the robot, end exactly at the goal
  if ((plan.waypoints_W.front() - start.position_W).norm() >
      search.costs().geometry().resolution_m) {
    plan.waypoints_W.insert(plan.waypoints_W.begin(), start.position_W);
  } else {
    plan.waypoints_W.front() = start.position_W;
  }
  if (plan.path.status == PlanStatus::kFound) plan.waypoints_W.back() = goal_W;

  const common::Stopwatch optimization_start;
  plan.optimized =
      optimizer_.Optimize(costs.field(), RequestAlong(start, plan.waypoints_W, obstacles));
  plan.status = plan.path.status == PlanStatus::kFound ? NavigationStatus::kPlanned
                                                       : NavigationStatus::kPlannedToNearest;
  if (plan.optimized.status == OptimizationStatus::kInfeasible) {
    FallBack(costs, start, search_start_W, obstacles, followed, &plan);
  }
  plan.optimization_time_s = optimization_start.ElapsedSeconds();
  return plan;
}

void NavigationPlanner::FallBack(const CostMap& costs, const common::TrajectoryPoint& start,
                                 const Eigen::Vector2d& search_start_W,
                                 const std::vector<MovingObstacle>& obstacles,
                                 const common::Trajectory* followed, NavigationPlan* plan) {
  const CostField& field = costs.field();
  const double resolution_m = field.geometry().resolution_m;
  // the manoeuvres keep the desired clearance, not the smallest: they are slow and taken without
  // optimisation, the map may show less of an obstacle than there is, and a turn sweeps the
  // corners
  const double clearance_m = config_.optimizer.clearance_m;
  const std::vector<Eigen::Vector2d> body_B =
      BodyPoints_B(config_.footprint, resolution_m, clearance_m);
  const OptimizationDiagnostics failed = plan->optimized.diagnostics;
  auto take = [&](common::Trajectory trajectory, Fallback fallback) {
    plan->optimized = OptimizedTrajectory{};
    plan->optimized.status = OptimizationStatus::kConverged;
    plan->optimized.trajectory = std::move(trajectory);
    plan->optimized.diagnostics = failed;
    plan->fallback = fallback;
  };
  // 1. a path on which the robot can turn anywhere, optimised
  const GridPlanner wide(costs.wide_search());
  const GridPath wide_path = search_(wide.costs(), search_start_W, plan->path.goal_W);
  if (wide_path.status == PlanStatus::kFound) {
    std::vector<Eigen::Vector2d> guide_W =
        wide.Simplify(wide_path.points_W, config_.simplify_tolerance);
    guide_W.front() = start.position_W;
    guide_W.back() = plan->waypoints_W.back();
    OptimizedTrajectory widened =
        optimizer_.Optimize(field, RequestAlong(start, guide_W, obstacles));
    if (widened.status != OptimizationStatus::kInfeasible) {
      plan->optimized = std::move(widened);
      plan->waypoints_W = std::move(guide_W);
      plan->fallback = Fallback::kWiderMargin;
      return;
    }
  }
  // 2. to 5. are slow manoeuvres that begin at rest where the robot is: a robot faster than they
  // go stops first, along its heading's arc, and they are planned from rest at a later replan
  // (begun at speed, the robot ran on past their start and the tracker pulled it back while it
  // turned); along the trajectory it is on where that keeps its footprint farther from obstacles
  // than the heading's arc (where the way turns or straightens ahead, the arc does not)
  if (std::abs(start.v) > config_.fallback.creep_speed_m_s) {
    take(SaferStop(field, start, followed, body_B, config_.fallback), Fallback::kStop);
    plan->status = NavigationStatus::kOptimizerFailed;  // it frees nothing and leads nowhere
    return;
  }
  // 2. the search path itself, slowly
  common::Trajectory creep = CreepAlong(start, plan->waypoints_W, false, config_.fallback);
  if (KeepsClear(field, creep, body_B, clearance_m)) {
    take(std::move(creep), Fallback::kFollowPath);
    return;
  }
  // 3. the footprint's own way, turning where it fits, to a point of the search path ahead
  if (config_.fallback.search_expansions > 0) {
    common::Pose2 from;
    from.position = start.position_W;
    from.yaw = start.yaw;
    const std::optional<std::vector<common::Pose2>> poses = SearchPoses(
        field, body_B, config_.footprint.CircumscribedRadius(), clearance_m, from,
        PointAlong(plan->waypoints_W, config_.fallback.search_reach_m), config_.fallback);
    if (poses && !poses->empty()) {
      common::Trajectory turns_and_drives = CreepThrough(start, *poses, config_.fallback);
      if (KeepsClear(field, turns_and_drives, body_B, clearance_m)) {
        plan->commit_until_s =
            NarrowsEnd(field, turns_and_drives,
                       config_.footprint.CircumscribedRadius() + config_.optimizer.clearance_m);
        take(std::move(turns_and_drives), Fallback::kPoseSearch);
        return;
      }
    }
  }
  // 4. a turn toward the path, then 5. a reverse drive, that only free the robot
  plan->status = NavigationStatus::kOptimizerFailed;
  const Eigen::Vector2d towards = plan->waypoints_W.size() < 2
                                      ? Eigen::Vector2d(Eigen::Vector2d::Zero())
                                      : Eigen::Vector2d(plan->waypoints_W[1] - start.position_W);
  const double heading = std::atan2(towards.y(), towards.x());
  if (towards.norm() > 0.0 &&
      std::abs(std::remainder(heading - start.yaw, 2.0 * M_PI)) > kAlignedYaw_rad) {
    common::Trajectory turn = TurnInPlace(start, heading, config_.fallback);
    if (KeepsClear(field, turn, body_B, clearance_m)) {
      take(std::move(turn), Fallback::kTurnInPlace);
      return;
    }
  }
  const Eigen::Vector2d backwards(-std::cos(start.yaw), -std::sin(start.yaw));
  for (double d = config_.fallback.back_out_distance_m; d >= resolution_m; d -= resolution_m) {
    common::Trajectory back = CreepAlong(
        start, {start.position_W, start.position_W + d * backwards}, true, config_.fallback);
    if (KeepsClear(field, back, body_B, clearance_m)) {
      take(std::move(back), Fallback::kBackOut);
      return;
    }
  }
}

}  // namespace trav::planner
