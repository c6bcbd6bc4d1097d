#include "planner/navigation_planner.h"

#include <chrono>

#include "planner/cost_field.h"

namespace trav::planner {
namespace {

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

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
    : config_(config), optimizer_(config.optimizer) {}

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
