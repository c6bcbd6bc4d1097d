#include "planner/cost_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "planner/cost_field.h"

namespace trav::planner {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Per-cell cost for the search (infinity = blocked), with the inflation applied to the known
// lethal cells (unknown cells blocked by the policy are not grown).
Eigen::MatrixXd SearchCosts(const common::GridGeometry& g, const Eigen::MatrixXf& layer,
                            const CostMapConfig& config) {
  Eigen::MatrixXd costs(g.num_x, g.num_y);
  std::vector<Eigen::Vector2i> lethal;
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      const float c = layer(ix, iy);
      if (IsLethal(c, config)) {
        costs(ix, iy) = kInfinity;
        if (!std::isnan(c)) lethal.emplace_back(ix, iy);
      } else {
        costs(ix, iy) = std::isnan(c) ? config.unknown_cost : std::max(0.0f, c);
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

bool IsLethal(float cost, const CostMapConfig& config) {
  if (std::isnan(cost)) return config.unknown_policy == UnknownPolicy::kBlocked;
  return cost >= config.lethal_threshold;
}

SearchCostMap::SearchCostMap(const common::GridLayers& map, const CostMapConfig& config)
    : SearchCostMap(map.geometry(), map.Layer(config.cost_layer), config) {}

SearchCostMap::SearchCostMap(const common::GridGeometry& geometry, const Eigen::MatrixXf& layer,
                             const CostMapConfig& config)
    : geometry_(geometry),
      config_(config),
      costs_(SearchCosts(geometry, layer, config)),
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

CostMap::CostMap(const common::GridLayers& map, const CostMapConfig& config)
    : geometry_(map.geometry()), config_(config), layer_(map.Layer(config.cost_layer)) {}

CostMap::~CostMap() = default;
CostMap::CostMap(CostMap&&) noexcept = default;
CostMap& CostMap::operator=(CostMap&&) noexcept = default;

bool CostMap::LethalAt(const Eigen::Vector2d& p_W) const {
  const std::optional<Eigen::Vector2i> cell = geometry_.CellIndex(p_W);
  return cell && IsLethal(layer_(cell->x(), cell->y()), config_);
}

const SearchCostMap& CostMap::search() const {
  if (!search_) search_ = std::make_unique<SearchCostMap>(geometry_, layer_, config_);
  return *search_;
}

const CostField& CostMap::field() const {
  if (!field_) field_ = std::make_unique<CostField>(geometry_, layer_, config_);
  return *field_;
}

}  // namespace trav::planner
