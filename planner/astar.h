#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "common/grid.h"
#include "planner/cost_map.h"

namespace trav::planner {

/// Settings of the grid search: how the map becomes search costs (see CostMapConfig).
using AStarConfig = CostMapConfig;

/// Outcome of a search.
enum class PlanStatus {
  kFound,         ///< a path to the goal
  kGoalMoved,     ///< the goal was blocked, unknown or walled off: a path to another cell instead
  kStartBlocked,  ///< the start cell is blocked (or outside the map)
  kNoPath,        ///< nothing reachable
};

/// A path on the grid.
struct GridPath {
  PlanStatus status{PlanStatus::kNoPath};
  std::vector<Eigen::Vector2d> points_W;            ///< cell centres from start to goal [m]
  Eigen::Vector2d goal_W{Eigen::Vector2d::Zero()};  ///< the goal reached (moved if kGoalMoved)
  double cost{0.0};                                 ///< sum of L (1 + w c) over the edges
  int expansions{0};                                ///< cells taken from the open list
};

/// A* on an 8-connected grid (Hart, Nilsson, Raphael 1968) over one map. The constructor turns the
/// map into search costs once (a SearchCostMap: lethal cells grown by the inflation radius, unknown
/// cells per the policy), so replanning and simplifying on the same map cost no more. Edge cost
/// L (1 + w c), L the edge length [m] and c the mean cost of its two cells; the heuristic is the
/// octile distance times (1 + w c_min), admissible because every edge costs at least that per
/// metre. A blocked goal (or one off the map) is moved to the reachable cell nearest to it. The map
/// is a window on a larger world, and what lies beyond its edge is unknown: a free goal walled off
/// within the map, and a goal off the map (in the operating area) whose nearest reachable cell is
/// not on the map's open edge or whose straight line on from that cell crosses an obstacle the
/// robot remembers (SearchCostMap::memory), are moved to the map's edge, where the way may go on:
/// to the reachable edge cell with unknown ground in the operating area beyond it (under
/// UnknownPolicy::kCost) whose cost from the start plus the way on to the goal at the unknown
/// cells' cost is least; the way on is the straight line, or where that crosses a remembered
/// obstacle the way round the remembered obstacles (ObstacleMemory::DistancesFrom, a path on the
/// grid: up to 8 % longer than a straight line, which favours the unobstructed cells a little);
/// where the remembered obstacles wall every edge cell off, the straight line ranks them all.
/// Deterministic (ties broken by cell index). No path is a status, not an error.
class GridPlanner {
 public:
  /// @throws std::out_of_range if the map lacks `config.cost_layer`.
  GridPlanner(const common::GridLayers& map, const AStarConfig& config);

  /// On search costs built before (a CostMap's), which must outlive the planner.
  explicit GridPlanner(const SearchCostMap& costs) : costs_(&costs) {}

  GridPlanner(const GridPlanner&) = delete;
  GridPlanner& operator=(const GridPlanner&) = delete;

  /// A path from start_W to goal_W.
  GridPath Plan(const Eigen::Vector2d& start_W, const Eigen::Vector2d& goal_W) const;

  /// Waypoints of `path` with every point dropped that the straight segment between its neighbours
  /// can skip without crossing a blocked cell or a cell costlier than the skipped stretch's own
  /// cells by more than `cost_tolerance` (line of sight on the grid). Keeps the first and last
  /// points.
  std::vector<Eigen::Vector2d> Simplify(const std::vector<Eigen::Vector2d>& path,
                                        double cost_tolerance = 0.1) const;

  /// The search costs built from the map.
  const SearchCostMap& costs() const { return *costs_; }

 private:
  std::optional<SearchCostMap> owned_costs_;  // built from a map by the planner itself
  const SearchCostMap* costs_;
};

}  // namespace trav::planner
