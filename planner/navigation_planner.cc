#include "planner/navigation_planner.h"

#include <chrono>

#include "common/input_error.h"
#include "planner/cost_field.h"

namespace trav::planner {
namespace {

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

void ValidateNavigationPlannerConfig(const NavigationPlannerConfig& c) {
  using common::RequireValue;
  const CostMapConfig& s = c.search;
  RequireValue(s.cost_weight >= 0.0, "planner.search.cost_weight", s.cost_weight, "must be >= 0");
  RequireValue(s.lethal_threshold > 0.0 && s.lethal_threshold <= 1.0,
               "planner.search.lethal_threshold", s.lethal_threshold, "must be in (0, 1]");
  RequireValue(s.inflation_radius_m >= 0.0, "planner.search.inflation_radius", s.inflation_radius_m,
               "must be >= 0");
  RequireValue(s.unknown_cost >= 0.0 && s.unknown_cost <= 1.0, "planner.search.unknown_cost",
               s.unknown_cost, "must be in [0, 1]");
  RequireValue(c.simplify_tolerance >= 0.0, "planner.search.simplify_tolerance",
               c.simplify_tolerance, "must be >= 0");
  ValidateTrajectoryOptimizerConfig(c.optimizer);
}

std::string ToString(NavigationStatus status) {
  switch (status) {
    case NavigationStatus::kPlanned:
      return "planned";
    case NavigationStatus::kPlannedToNearest:
      return "planned-to-nearest";
    case NavigationStatus::kOptimizerFailed:
      return "optimizer-failed";
    case NavigationStatus::kNoPath:
      return "no-path";
  }
  return "unknown";
}

NavigationPlanner::NavigationPlanner(const NavigationPlannerConfig& config)
    : config_(config), optimizer_(config.optimizer) {
  ValidateNavigationPlannerConfig(config_);
}

NavigationPlan NavigationPlanner::Plan(const common::GridLayers& map,
                                       const common::TrajectoryPoint& start,
                                       const Eigen::Vector2d& goal_W,
                                       const std::vector<MovingObstacle>& obstacles) {
  NavigationPlan plan;
  const auto search_start = std::chrono::steady_clock::now();
  const GridPlanner search(map, config_.search);
  plan.path = search.Plan(start.position_W, goal_W);
  if (plan.path.status == PlanStatus::kFound || plan.path.status == PlanStatus::kGoalMoved) {
    plan.waypoints_W = search.Simplify(plan.path.points_W, config_.simplify_tolerance);
  }
  plan.search_time_s = SecondsSince(search_start);
  if (plan.waypoints_W.empty()) {
    plan.status = NavigationStatus::kNoPath;
    return plan;
  }
  // the path runs between cell centres: start exactly at the robot, end exactly at the goal
  plan.waypoints_W.front() = start.position_W;
  if (plan.path.status == PlanStatus::kFound) plan.waypoints_W.back() = goal_W;

  const auto optimization_start = std::chrono::steady_clock::now();
  const CostField field(map, config_.search);
  TrajectoryRequest request;
  request.start = start;
  request.goal_W = plan.waypoints_W.back();
  request.guide_W = plan.waypoints_W;
  request.obstacles = obstacles;
  plan.optimized = optimizer_.Optimize(field, request);
  plan.optimization_time_s = SecondsSince(optimization_start);
  if (plan.optimized.status == OptimizationStatus::kInfeasible) {
    plan.status = NavigationStatus::kOptimizerFailed;
  } else {
    plan.status = plan.path.status == PlanStatus::kFound ? NavigationStatus::kPlanned
                                                         : NavigationStatus::kPlannedToNearest;
  }
  return plan;
}

}  // namespace trav::planner
