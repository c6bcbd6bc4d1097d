#include "planner/obstacle_memory.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <queue>
#include <utility>
#include <vector>

#include "common/check.h"

namespace trav::planner {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Cell centres closer to a lattice point than this fraction of a cell lie on the lattice.
constexpr double kLatticeTolerance = 1e-6;

}  // namespace

ObstacleMemory::ObstacleMemory(const Eigen::AlignedBox2d& area_W,
                               const common::GridGeometry& map_lattice) {
  TRAV_DEMAND(!area_W.isEmpty() && map_lattice.resolution_m > 0.0);
  const Eigen::Vector2i low = map_lattice.NearestLatticeIndex(area_W.min());
  const Eigen::Vector2i high = map_lattice.NearestLatticeIndex(area_W.max());
  geometry_.origin_W = map_lattice.CellCenter(low.x(), low.y());
  geometry_.resolution_m = map_lattice.resolution_m;
  geometry_.num_x = high.x() - low.x() + 1;
  geometry_.num_y = high.y() - low.y() + 1;
  blocked_.setZero(geometry_.num_x, geometry_.num_y);
}

bool ObstacleMemory::SharesLattice(const common::GridGeometry& map) const {
  if (map.resolution_m != geometry_.resolution_m) return false;
  const Eigen::Vector2d offset = (map.origin_W - geometry_.origin_W) / geometry_.resolution_m;
  return (offset.array() - offset.array().round()).abs().maxCoeff() < kLatticeTolerance;
}

void ObstacleMemory::Record(const common::GridGeometry& map, const Eigen::MatrixXf& layer,
                            const CostMapConfig& config) {
  TRAV_DEMAND(SharesLattice(map) && layer.rows() == map.num_x && layer.cols() == map.num_y);
  // the map's cell (ix, iy) is the memory's (ix + shift.x, iy + shift.y)
  const Eigen::Vector2i shift = geometry_.NearestLatticeIndex(map.origin_W);
  const int x_begin = std::max(0, -shift.x()),
            x_end = std::min(map.num_x, geometry_.num_x - shift.x());
  const int y_begin = std::max(0, -shift.y()),
            y_end = std::min(map.num_y, geometry_.num_y - shift.y());
  for (int iy = y_begin; iy < y_end; ++iy) {
    for (int ix = x_begin; ix < x_end; ++ix) {
      const float cost = layer(ix, iy);
      if (std::isnan(cost)) continue;
      blocked_(ix + shift.x(), iy + shift.y()) = IsLethal(cost, config) ? 1 : 0;
    }
  }
}

bool ObstacleMemory::Blocked(const Eigen::Vector2d& p_W) const {
  const std::optional<Eigen::Vector2i> cell = geometry_.CellIndex(p_W);
  return cell && blocked_(cell->x(), cell->y()) != 0;
}

bool ObstacleMemory::Obstructed(const Eigen::Vector2d& a_W, const Eigen::Vector2d& b_W) const {
  const int samples =
      static_cast<int>(std::ceil((b_W - a_W).norm() / (0.5 * geometry_.resolution_m))) + 1;
  for (int k = 0; k <= samples; ++k) {
    if (Blocked(a_W + (b_W - a_W) * (static_cast<double>(k) / samples))) return true;
  }
  return false;
}

Eigen::MatrixXd ObstacleMemory::DistancesFrom(const Eigen::Vector2d& goal_W) const {
  const common::GridGeometry& g = geometry_;
  Eigen::MatrixXd distance_m = Eigen::MatrixXd::Constant(g.num_x, g.num_y, kInfinity);
  const Eigen::Vector2i source = g.NearestLatticeIndex(goal_W)
                                     .cwiseMax(Eigen::Vector2i::Zero())
                                     .cwiseMin(Eigen::Vector2i(g.num_x - 1, g.num_y - 1));
  auto free = [&](int ix, int iy) { return g.Contains(ix, iy) && blocked_(ix, iy) == 0; };
  // Dijkstra, written here as A* is (planner/astar.cc): a graph library would first copy the grid
  // and its moves into a graph of its own, which costs more than the search
  using Entry = std::pair<double, int>;  // (distance, linear index): ties go to the lower index
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  distance_m(source.x(), source.y()) = 0.0;
  open.emplace(0.0, source.x() + source.y() * g.num_x);
  const double diagonal_m = std::sqrt(2.0) * g.resolution_m;
  while (!open.empty()) {
    const auto [d, index] = open.top();
    open.pop();
    const int ix = index % g.num_x, iy = index / g.num_x;
    if (d > distance_m(ix, iy)) continue;  // stale entry
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        if ((dx == 0 && dy == 0) || !free(ix + dx, iy + dy)) continue;
        const bool diagonal = dx != 0 && dy != 0;
        if (diagonal && (!free(ix + dx, iy) || !free(ix, iy + dy))) continue;
        const double candidate = d + (diagonal ? diagonal_m : g.resolution_m);
        if (candidate < distance_m(ix + dx, iy + dy)) {
          distance_m(ix + dx, iy + dy) = candidate;
          open.emplace(candidate, ix + dx + (iy + dy) * g.num_x);
        }
      }
    }
  }
  return distance_m;
}

}  // namespace trav::planner
