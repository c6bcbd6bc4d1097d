#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/archive.h"
#include "common/enum_names.h"
#include "common/grid.h"
#include "common/trajectory.h"
#include "planner/astar.h"
#include "planner/trajectory_optimizer.h"

namespace trav::planner {

/// Settings of the whole planner (scenario key `planner`).
struct NavigationPlannerConfig {
  AStarConfig search;              ///< how the map is read and searched
  double simplify_tolerance{0.1};  ///< cost slack of line-of-sight simplification
  /// A substitute goal (the reachable cell nearest to an unreachable goal) is kept until the robot
  /// is this close to it [m], > 0.
  double substitute_goal_reach_m{3.0};
  TrajectoryOptimizerConfig optimizer;  ///< trajectory optimisation

  /// The keys of scenario section `planner` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Map("search", [this](Archive& k) {
      search.Serialize(&k);
      k.Field("simplify_tolerance", &simplify_tolerance, {0, 10});
      k.Field("substitute_goal_reach", &substitute_goal_reach_m, {0, 100});
    });
    a->Map("optimizer", &optimizer);
  }
};

/// Checks a config. @throws common::InputError naming the key (relative: "search.cost_weight",
/// "optimizer.clearance") and the value.
void ValidateNavigationPlannerConfig(const NavigationPlannerConfig& config);

/// How a planning call ended.
enum class NavigationStatus {
  kPlanned,           ///< a trajectory to the goal
  kPlannedToNearest,  ///< the goal was blocked or unknown: a trajectory to the reachable cell
                      ///< nearest to it
  kOptimizerFailed,   ///< a path exists but the optimised trajectory violates a constraint
  kNoPath,            ///< the search found no path (or the start is blocked)
};

/// The names of NavigationStatus's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<NavigationStatus>, 4> kNavigationStatusNames{
    {{NavigationStatus::kPlanned, "planned"},
     {NavigationStatus::kPlannedToNearest, "planned-to-nearest"},
     {NavigationStatus::kOptimizerFailed, "optimizer-failed"},
     {NavigationStatus::kNoPath, "no-path"}}};
constexpr const auto& EnumNames(NavigationStatus) { return kNavigationStatusNames; }

/// Result of one planning call.
struct NavigationPlan {
  NavigationStatus status{NavigationStatus::kNoPath};
  GridPath path;                             ///< the A* path (cell centres)
  std::vector<Eigen::Vector2d> waypoints_W;  ///< its simplification, from the start to the goal
  OptimizedTrajectory optimized;             ///< empty trajectory if there was no path
  double search_time_s{0.0};                 ///< A* wall time, including the map's search costs
  double optimization_time_s{0.0};           ///< optimiser wall time

  bool has_trajectory() const { return !optimized.trajectory.empty(); }
};

/// The planning stack on one traversability map: A* on the grid, line-of-sight simplification into
/// waypoints, and trajectory optimisation along them with the moving obstacles' predictions. A
/// start inside the inflation of lethal cells searches from the nearest free cell within the
/// inflation radius plus two cells (the trajectory leaves from the robot itself). When the goal
/// cannot be reached on the map (unknown or outside it), the planner heads for the reachable cell
/// nearest to it and keeps that substitute while it stays reachable, until the robot comes within
/// `substitute_goal_reach_m` of it (a receding horizon that does not dither). Keeps
/// the previous trajectory for warm starts (TrajectoryOptimizer). Failure is a status.
class NavigationPlanner {
 public:
  /// @throws common::InputError for an invalid config.
  explicit NavigationPlanner(const NavigationPlannerConfig& config);

  /// Plans from `start` (time, pose and velocities) to goal_W on `map`.
  /// @throws std::out_of_range if the map lacks the cost layer.
  NavigationPlan Plan(const common::GridLayers& map, const common::TrajectoryPoint& start,
                      const Eigen::Vector2d& goal_W, const std::vector<MovingObstacle>& obstacles);

  /// Plans on a map's costs built before (with this planner's `config().search`), so that plans
  /// on one map share them.
  NavigationPlan Plan(const CostMap& costs, const common::TrajectoryPoint& start,
                      const Eigen::Vector2d& goal_W, const std::vector<MovingObstacle>& obstacles);

  /// Forgets the previous trajectory and substitute goal.
  void Reset() {
    optimizer_.Reset();
    substitute_goal_W_.reset();
  }

  const NavigationPlannerConfig& config() const { return config_; }

 private:
  NavigationPlannerConfig config_;
  TrajectoryOptimizer optimizer_;
  std::optional<Eigen::Vector2d> substitute_goal_W_;
};

}  // namespace trav::planner
