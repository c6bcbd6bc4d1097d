#include "planner/cost_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

namespace trav::planner {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Per-cell cost for the search (infinity = blocked), with the inflation applied.
Eigen::MatrixXd SearchCosts(const common::GridLayers& map, const CostMapConfig& config) {
  const common::GridGeometry& g = map.geometry();
  const Eigen::MatrixXf& layer = map.Layer(config.cost_layer);
  Eigen::MatrixXd costs(g.num_x, g.num_y);
  std::vector<Eigen::Vector2i> lethal;
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      const float c = layer(ix, iy);
      if (std::isnan(c)) {
        costs(ix, iy) =
            config.unknown_policy == UnknownPolicy::kBlocked ? kInfinity : config.unknown_cost;
      } else if (c >= config.lethal_threshold) {
        costs(ix, iy) = kInfinity;
        lethal.emplace_back(ix, iy);
      } else {
        costs(ix, iy) = std::max(0.0f, c);
      }
    }
  }
  // grow the lethal cells by the footprint radius (a disc of cells)
  const int r = static_cast<int>(std::floor(config.inflation_radius_m / g.resolution_m + 1e-9));
  for (const Eigen::Vector2i& cell : lethal) {
    for (int dx = -r; dx <= r; ++dx) {
      for (int dy = -r; dy <= r; ++dy) {
        if (dx * dx + dy * dy > r * r || !g.Contains(cell.x() + dx, cell.y() + dy)) continue;
        costs(cell.x() + dx, cell.y() + dy) = kInfinity;
      }
    }
  }
  return costs;
}

double MinFiniteCost(const Eigen::MatrixXd& costs) {
  double cheapest = kInfinity;
  for (Eigen::Index i = 0; i < costs.size(); ++i) cheapest = std::min(cheapest, costs.data()[i]);
  return std::isfinite(cheapest) ? cheapest : 0.0;
}

}  // namespace

SearchCostMap::SearchCostMap(const common::GridLayers& map, const CostMapConfig& config)
    : geometry_(map.geometry()),
      config_(config),
      costs_(SearchCosts(map, config)),
      min_cost_(MinFiniteCost(costs_)) {}

double SearchCostMap::CostAt(const Eigen::Vector2d& p_W) const {
  const std::optional<Eigen::Vector2i> cell = geometry_.CellIndex(p_W);
  return cell ? costs_(cell->x(), cell->y()) : kInfinity;
}

double SearchCostMap::SegmentCost(const Eigen::Vector2d& a_W, const Eigen::Vector2d& b_W) const {
  if (!a_W.allFinite() || !b_W.allFinite()) return kInfinity;
  // sample from the lexicographically smaller end so that the cost is symmetric bit for bit
  const bool swap = std::make_pair(b_W.x(), b_W.y()) < std::make_pair(a_W.x(), a_W.y());
  const Eigen::Vector2d& from = swap ? b_W : a_W;
  const Eigen::Vector2d& to = swap ? a_W : b_W;
  // both ends on free cells first: this also bounds the number of samples by the grid's size
  const double cost_from = CostAt(from), cost_to = CostAt(to);
  if (!std::isfinite(cost_from) || !std::isfinite(cost_to)) return kInfinity;
  const double length = (to - from).norm();
  const int intervals = static_cast<int>(std::ceil(length / (0.5 * geometry_.resolution_m)));
  if (intervals == 0) return 0.0;
  double sum = cost_from + cost_to;
  for (int k = 1; k < intervals; ++k) {
    const double c = CostAt(from + (to - from) * (static_cast<double>(k) / intervals));
    if (!std::isfinite(c)) return kInfinity;
    sum += c;
  }
  return length * (1.0 + config_.cost_weight * sum / (intervals + 1));
}

}  // namespace trav::planner
