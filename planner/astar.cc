#include "planner/astar.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "planner/obstacle_memory.h"

namespace trav::planner {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr int kMoves[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {1, -1}, {-1, 1}, {-1, -1}};

struct Search {
  Eigen::MatrixXd g_cost;  // cost from the start
  Eigen::MatrixXi parent;  // linear index of the parent, -1 none
  int expansions{0};
};

// A* (or Dijkstra when `goal` is null) from `start` over finite costs.
Search Run(const SearchCostMap& costs, const Eigen::Vector2i& start, const Eigen::Vector2i* goal) {
  const common::GridGeometry& g = costs.geometry();
  Search search;
  search.g_cost = Eigen::MatrixXd::Constant(g.num_x, g.num_y, kInfinity);
  search.parent = Eigen::MatrixXi::Constant(g.num_x, g.num_y, -1);
  // every edge costs at least its length times (1 + w c_min): the octile distance scaled by that
  // stays admissible and is much tighter on maps without free cells
  const double w = costs.config().cost_weight;
  const double scale = g.resolution_m * (1.0 + w * costs.min_cost());
  auto heuristic = [&](int ix, int iy) {
    if (goal == nullptr) return 0.0;
    const double dx = std::abs(ix - goal->x()), dy = std::abs(iy - goal->y());
    return scale * (std::max(dx, dy) + (std::sqrt(2.0) - 1.0) * std::min(dx, dy));
  };
  using Entry = std::pair<double, int>;  // (f, linear index): ties go to the lower index
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  search.g_cost(start.x(), start.y()) = 0.0;
  open.emplace(heuristic(start.x(), start.y()), start.x() + start.y() * g.num_x);
  while (!open.empty()) {
    const auto [f, index] = open.top();
    open.pop();
    const int ix = index % g.num_x, iy = index / g.num_x;
    if (f > search.g_cost(ix, iy) + heuristic(ix, iy) + 1e-12) continue;  // stale entry
    ++search.expansions;
    if (goal != nullptr && ix == goal->x() && iy == goal->y()) break;
    for (const auto& move : kMoves) {
      const int jx = ix + move[0], jy = iy + move[1];
      if (!g.Contains(jx, jy) || !std::isfinite(costs.cost(jx, jy))) continue;
      const double length = g.resolution_m * (move[0] != 0 && move[1] != 0 ? std::sqrt(2.0) : 1.0);
      const double step = length * (1.0 + w * 0.5 * (costs.cost(ix, iy) + costs.cost(jx, jy)));
      const double candidate = search.g_cost(ix, iy) + step;
      if (candidate < search.g_cost(jx, jy)) {
        search.g_cost(jx, jy) = candidate;
        search.parent(jx, jy) = index;
        open.emplace(candidate + heuristic(jx, jy), jx + jy * g.num_x);
      }
    }
  }
  return search;
}

// True if cell (ix, iy) lies on the map's edge with the way open beyond it: unknown ground (under
// UnknownPolicy::kCost) in the operating area.
bool OnOpenEdge(const SearchCostMap& costs, int ix, int iy) {
  const CostMapConfig& config = costs.config();
  if (config.unknown_policy != UnknownPolicy::kCost) return false;
  const common::GridGeometry& g = costs.geometry();
  auto open_beyond = [&](int dx, int dy) {
    return config.InOperatingArea(g.CellCenter(ix + dx, iy + dy));
  };
  return (ix == 0 && open_beyond(-1, 0)) || (ix == g.num_x - 1 && open_beyond(1, 0)) ||
         (iy == 0 && open_beyond(0, -1)) || (iy == g.num_y - 1 && open_beyond(0, 1));
}

// The way on from a point of the map to goal_W [m], as far as the map cannot tell: the straight
// line, or where that crosses an obstacle the robot remembers (ObstacleMemory), the way round the
// remembered obstacles; infinity where they wall the point off.
class WayOn {
 public:
  WayOn(const ObstacleMemory* memory, const Eigen::Vector2d& goal_W)
      : memory_(memory), goal_W_(goal_W) {}

  // True if the straight line from p_W crosses a remembered obstacle.
  bool Obstructed(const Eigen::Vector2d& p_W) const {
    return memory_ != nullptr && memory_->Obstructed(p_W, goal_W_);
  }

  double Length(const Eigen::Vector2d& p_W) {
    if (!Obstructed(p_W)) return (p_W - goal_W_).norm();
    if (!round_m_) round_m_ = memory_->DistancesFrom(goal_W_);
    const std::optional<Eigen::Vector2i> cell = memory_->geometry().CellIndex(p_W);
    return cell ? (*round_m_)(cell->x(), cell->y()) : kInfinity;
  }

 private:
  const ObstacleMemory* memory_;
  Eigen::Vector2d goal_W_;
  std::optional<Eigen::MatrixXd> round_m_;  // the memory's distances from the goal, once needed
};

// The reachable cell on the map's open edge from which the way to goal_W looks cheapest: its cost
// from the start plus the way on (WayOn) over unknown ground. Where the remembered obstacles wall
// every such cell off, the memory may be wrong (it keeps no gap narrower than a cell): the
// straight line instead. Ties go to the lower linear index. Nothing if no such cell.
std::optional<Eigen::Vector2i> ExitTowards(const SearchCostMap& costs, const Search& search,
                                           WayOn* way_on, const Eigen::Vector2d& goal_W) {
  const CostMapConfig& config = costs.config();
  const common::GridGeometry& g = costs.geometry();
  const double per_metre = 1.0 + config.cost_weight * config.unknown_cost;
  struct Best {
    double cost{kInfinity};
    int index{-1};
  } round, straight;  // by the way on, by the straight line
  auto consider = [&](int ix, int iy) {
    if (!std::isfinite(search.g_cost(ix, iy)) || !OnOpenEdge(costs, ix, iy)) return;
    const int index = ix + iy * g.num_x;
    auto take = [&](Best* best, double cost) {
      if (cost < best->cost || (cost == best->cost && index < best->index)) *best = {cost, index};
    };
    const Eigen::Vector2d p_W = g.CellCenter(ix, iy);
    take(&round, search.g_cost(ix, iy) + per_metre * way_on->Length(p_W));
    take(&straight, search.g_cost(ix, iy) + per_metre * (p_W - goal_W).norm());
  };
  for (int ix = 0; ix < g.num_x; ++ix) {
    consider(ix, 0);
    if (g.num_y > 1) consider(ix, g.num_y - 1);
  }
  for (int iy = 1; iy + 1 < g.num_y; ++iy) {
    consider(0, iy);
    if (g.num_x > 1) consider(g.num_x - 1, iy);
  }
  const int index = std::isfinite(round.cost) ? round.index : straight.index;
  if (index < 0) return std::nullopt;
  return Eigen::Vector2i(index % g.num_x, index / g.num_x);
}

}  // namespace

GridPlanner::GridPlanner(const common::GridLayers& map, const AStarConfig& config)
    : owned_costs_(std::in_place, map, config), costs_(&*owned_costs_) {}

GridPath GridPlanner::Plan(const Eigen::Vector2d& start_W, const Eigen::Vector2d& goal_W) const {
  GridPath path;
  const common::GridGeometry& g = costs_->geometry();
  const std::optional<Eigen::Vector2i> start = g.CellIndex(start_W);
  if (!start || !std::isfinite(costs_->cost(start->x(), start->y()))) {
    path.status = PlanStatus::kStartBlocked;
    return path;
  }
  std::optional<Eigen::Vector2i> goal = g.CellIndex(goal_W);
  Search search;
  if (goal && std::isfinite(costs_->cost(goal->x(), goal->y()))) {
    search = Run(*costs_, *start, &*goal);
    path.status = PlanStatus::kFound;
    if (!std::isfinite(search.g_cost(goal->x(), goal->y()))) {
      // walled off within the map (A* has costed every reachable cell on the way): the way may
      // lie beyond the map's edge
      WayOn way_on(costs_->memory(), goal_W);
      goal = ExitTowards(*costs_, search, &way_on, goal_W);
      path.status = PlanStatus::kGoalMoved;
    }
  } else {
    // a blocked, unknown-and-blocked or outside goal: the reachable cell nearest to it
    search = Run(*costs_, *start, nullptr);
    double best = kInfinity;
    for (int iy = 0; iy < g.num_y; ++iy) {
      for (int ix = 0; ix < g.num_x; ++ix) {
        if (!std::isfinite(search.g_cost(ix, iy))) continue;
        const double d = (g.CellCenter(ix, iy) - goal_W).norm();
        if (d < best) {
          best = d;
          goal = Eigen::Vector2i(ix, iy);
        }
      }
    }
    // a goal off the map is reached across the map's edge: where the reachable cell nearest to
    // it is not on the open edge, the way toward it is walled off within the map (a dead end);
    // where the straight line on from it crosses an obstacle the robot remembers, the way on may
    // be shorter from elsewhere (a dead end that has left the map)
    WayOn way_on(costs_->memory(), goal_W);
    if (goal && !g.CellIndex(goal_W) && costs_->config().InOperatingArea(goal_W) &&
        (!OnOpenEdge(*costs_, goal->x(), goal->y()) ||
         way_on.Obstructed(g.CellCenter(goal->x(), goal->y())))) {
      if (const std::optional<Eigen::Vector2i> exit =
              ExitTowards(*costs_, search, &way_on, goal_W)) {
        goal = exit;
      }
    }
    path.status = PlanStatus::kGoalMoved;
  }
  path.expansions = search.expansions;
  if (!goal || !std::isfinite(search.g_cost(goal->x(), goal->y()))) {
    path.status = PlanStatus::kNoPath;
    return path;
  }
  path.cost = search.g_cost(goal->x(), goal->y());
  path.goal_W = g.CellCenter(goal->x(), goal->y());
  for (int index = goal->x() + goal->y() * g.num_x; index >= 0;
       index = search.parent(index % g.num_x, index / g.num_x)) {
    path.points_W.push_back(g.CellCenter(index % g.num_x, index / g.num_x));
  }
  std::reverse(path.points_W.begin(), path.points_W.end());
  return path;
}

std::vector<Eigen::Vector2d> GridPlanner::Simplify(const std::vector<Eigen::Vector2d>& path,
                                                   double cost_tolerance) const {
  if (path.size() <= 2) return path;
  const common::GridGeometry& g = costs_->geometry();
  // the straight segment a-b stays on free cells no costlier than `limit`
  auto visible = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b, double limit) {
    const int samples = static_cast<int>(std::ceil((b - a).norm() / (0.5 * g.resolution_m))) + 1;
    for (int k = 0; k <= samples; ++k) {
      if (costs_->CostAt(a + (b - a) * (static_cast<double>(k) / samples)) > limit) return false;
    }
    return true;
  };
  std::vector<Eigen::Vector2d> waypoints = {path.front()};
  std::size_t anchor = 0;
  while (anchor + 1 < path.size()) {
    // the farthest point visible from the anchor within the cost of the skipped stretch
    std::size_t next = anchor + 1;
    double stretch_cost = std::max(costs_->CostAt(path[anchor]), costs_->CostAt(path[next]));
    for (std::size_t j = anchor + 2; j < path.size(); ++j) {
      stretch_cost = std::max(stretch_cost, costs_->CostAt(path[j]));
      if (!visible(path[anchor], path[j], stretch_cost + cost_tolerance)) break;
      next = j;
    }
    waypoints.push_back(path[next]);
    anchor = next;
  }
  return waypoints;
}

}  // namespace trav::planner
