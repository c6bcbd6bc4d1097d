#pragma once

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/archive.h"
#include "common/enum_names.h"
#include "common/footprint.h"
#include "common/grid.h"
#include "common/trajectory.h"
#include "planner/astar.h"
#include "planner/manoeuvres.h"
#include "planner/obstacle_memory.h"
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
  FallbackConfig fallback;              ///< the manoeuvres when optimisation fails
  /// The robot's outline (not a scenario key: the closed loop reads it from the robot file). It
  /// replaces `optimizer.footprint` and sets the search's inflation (SearchConfig).
  common::Footprint footprint;

  /// The search settings the planner applies, `search` with the footprint: a cell is blocked when
  /// the inscribed disc plus `optimizer.min_clearance` round its centre reaches a lethal cell (the
  /// optimiser's smallest clearance for a robot broadside to the obstacle), and pays
  /// `search.band_cost` more, less with the distance, while the circumscribed disc plus
  /// `optimizer.clearance` does (where the robot cannot turn freely); the terrain sets no speed
  /// limit above `optimizer.max_speed`. docs/navigation.md.
  CostMapConfig SearchConfig() const;

  /// The optimiser settings the planner applies: `optimizer` with `footprint`.
  TrajectoryOptimizerConfig OptimizerConfig() const;

  /// The keys of scenario section `planner` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Map("search", [this](Archive& k) {
      search.Serialize(&k);
      k.Field("simplify_tolerance", &simplify_tolerance, {0, 10});
      k.Field("substitute_goal_reach", &substitute_goal_reach_m, {0, 100});
    });
    a->Map("optimizer", &optimizer);
    a->Map("speed", &search.speed);
    a->Map("slope", &search.slope);
    a->Map("steps", &search.steps);
    a->Map("fallback", &fallback);
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

/// The manoeuvre a plan falls back on when the optimised trajectory violates a constraint, tried
/// in this order (docs/navigation.md).
enum class Fallback {
  kNone,         ///< the optimised trajectory along the search path
  kWiderMargin,  ///< optimised along a path searched with the circumscribed disc's margin
  kFollowPath,   ///< the search path itself at creep speed, turning in place at its vertices
  kPoseSearch,   ///< the footprint's own way (SearchPoses) to a point of the search path ahead
  kTurnInPlace,  ///< a turn in place toward the path's first segment
  kBackOut,      ///< a straight reverse drive
  kStop,  ///< a stop (StopFrom, or StopAlong the trajectory followed) before the slow manoeuvres
};

/// The names of Fallback's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<Fallback>, 7> kFallbackNames{
    {{Fallback::kNone, "none"},
     {Fallback::kWiderMargin, "wider-margin"},
     {Fallback::kFollowPath, "follow-path"},
     {Fallback::kPoseSearch, "pose-search"},
     {Fallback::kTurnInPlace, "turn-in-place"},
     {Fallback::kBackOut, "back-out"},
     {Fallback::kStop, "stop"}}};
constexpr const auto& EnumNames(Fallback) { return kFallbackNames; }

/// Result of one planning call.
struct NavigationPlan {
  NavigationStatus status{NavigationStatus::kNoPath};
  GridPath path;                             ///< the A* path (cell centres)
  std::vector<Eigen::Vector2d> waypoints_W;  ///< its simplification, from the start to the goal
  OptimizedTrajectory optimized;             ///< empty trajectory if there was no path
  /// What the trajectory is when optimisation failed. With kWiderMargin, kFollowPath and
  /// kPoseSearch the status stays kPlanned or kPlannedToNearest (it leads to the goal); with
  /// kTurnInPlace and kBackOut it is kOptimizerFailed with a trajectory that only frees the robot.
  Fallback fallback{Fallback::kNone};
  /// With kPoseSearch, the end of the way's last stretch where the robot cannot turn in place
  /// (its circumscribed disc plus `optimizer.clearance` reaches lethal cells), or its start if it
  /// has none: a navigator follows the way that far without periodic replanning, so that the next
  /// plan does not choose another way round while the robot is half-way through a gap.
  std::optional<double> commit_until_s;
  double search_time_s{0.0};        ///< A* wall time, including the map's search costs
  double optimization_time_s{0.0};  ///< optimiser wall time

  bool has_trajectory() const { return !optimized.trajectory.empty(); }
};

/// The planning stack on one traversability map: A* on the grid, line-of-sight simplification into
/// waypoints, and trajectory optimisation along them with the moving obstacles' predictions. A
/// start inside the inflation of lethal cells searches from the nearest free cell within the
/// inflation radius plus two cells (the trajectory leaves from the robot itself). When the goal
/// cannot be reached on the map (unknown or outside it), the planner heads for the reachable cell
/// nearest to it and keeps that substitute while it stays reachable, until the robot comes within
/// `substitute_goal_reach_m` of it (a receding horizon that does not dither). When the optimised
/// trajectory violates a constraint, the planner falls back, in order, on: an optimised trajectory
/// along a path searched with the circumscribed disc's margin; the search path at creep speed; the
/// footprint's own way of turns in place and straight drives to a point of that path ahead
/// (SearchPoses); a turn in place toward it; a straight reverse drive (Fallback); each only if the
/// footprint keeps the smallest clearance along it (KeepsClear). Keeps the previous trajectory for
/// warm starts (TrajectoryOptimizer). Failure is a status. A path search from start_W to goal_W on
/// search costs, as GridPlanner::Plan answers it (status, points from the start's cell to the
/// goal's): A* by default; scenarios/run offers OMPL's sampling planners and a user's own under the
/// scenario key `planner.method`.
using PathSearch = std::function<GridPath(
    const SearchCostMap& costs, const Eigen::Vector2d& start_W, const Eigen::Vector2d& goal_W)>;

/// A* (GridPlanner) on `costs`.
GridPath AStarSearch(const SearchCostMap& costs, const Eigen::Vector2d& start_W,
                     const Eigen::Vector2d& goal_W);

class NavigationPlanner {
 public:
  /// Plans with `search` for the path that the trajectory follows (A* unless given).
  /// @throws common::InputError for an invalid config.
  explicit NavigationPlanner(const NavigationPlannerConfig& config,
                             PathSearch search = AStarSearch);

  /// Plans from `start` (time, pose and velocities) to goal_W on `map`. `followed`, unless null,
  /// is the trajectory the robot is on at start.t_s: a stop at speed (Fallback::kStop) brakes along
  /// it instead of along the heading's arc where its footprint keeps farther from obstacles.
  /// @throws std::out_of_range if the map lacks the cost layer.
  NavigationPlan Plan(const common::GridLayers& map, const common::TrajectoryPoint& start,
                      const Eigen::Vector2d& goal_W, const std::vector<MovingObstacle>& obstacles,
                      const common::Trajectory* followed = nullptr);

  /// Plans on a map's costs built before (with this planner's `config().SearchConfig()` and the
  /// memory Remember returned for that map), so that plans on one map share them.
  NavigationPlan Plan(const CostMap& costs, const common::TrajectoryPoint& start,
                      const Eigen::Vector2d& goal_W, const std::vector<MovingObstacle>& obstacles,
                      const common::Trajectory* followed = nullptr);

  /// Adds what `map` shows to the planner's memory of obstacles (ObstacleMemory, on the search
  /// config's operating area) and returns the memory for the map's costs (CostMap); null without
  /// an operating area (the memory needs a bounded world). A map on another lattice than the
  /// memory's starts it afresh. A memory returned before is never changed: while something still
  /// holds it (a CostMap), the new one is a copy (one byte per cell of the operating area).
  /// @throws std::out_of_range if the map lacks the cost layer.
  std::shared_ptr<const ObstacleMemory> Remember(const common::GridLayers& map);

  /// Forgets the previous trajectory, substitute goal and remembered obstacles.
  void Reset() {
    optimizer_.Reset();
    substitute_goal_W_.reset();
    memory_.reset();
  }

  const NavigationPlannerConfig& config() const { return config_; }

 private:
  // The fallbacks of an optimisation that failed along plan->waypoints_W, in order (`followed`:
  // Plan's).
  void FallBack(const CostMap& costs, const common::TrajectoryPoint& start,
                const Eigen::Vector2d& search_start_W, const std::vector<MovingObstacle>& obstacles,
                const common::Trajectory* followed, NavigationPlan* plan);

  NavigationPlannerConfig config_;
  PathSearch search_;
  TrajectoryOptimizer optimizer_;
  std::optional<Eigen::Vector2d> substitute_goal_W_;
  std::shared_ptr<ObstacleMemory> memory_;  // copied on write while a CostMap shares it
};

}  // namespace trav::planner
