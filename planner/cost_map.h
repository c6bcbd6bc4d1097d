#pragma once

#include <string>

#include <Eigen/Core>

#include "common/grid.h"

namespace trav::planner {

/// How the search costs treat cells whose cost is unknown (NaN).
enum class UnknownPolicy {
  kCost,     ///< traversable at `unknown_cost`
  kBlocked,  ///< never entered
};

/// How a traversability layer becomes search costs; the settings of A* (`AStarConfig`) and of the
/// sampling planners.
struct CostMapConfig {
  std::string cost_layer{"traversability"};  ///< layer of costs in [0, 1]
  double cost_weight{5.0};                   ///< w in the cost L (1 + w c), >= 0
  double lethal_threshold{0.8};              ///< cells at or above this cost are blocked
  double inflation_radius_m{0.3};  ///< blocked cells grow by the robot's footprint radius [m]
  UnknownPolicy unknown_policy{UnknownPolicy::kCost};
  double unknown_cost{0.5};  ///< cost of an unknown cell under kCost
};

/// The per-cell cost c that every planner of this module pays, built once from a map: cells at or
/// above the lethal threshold are blocked (infinite cost) and grow by the inflation radius (a disc
/// of floor(radius / resolution) cells), unknown cells follow the unknown policy, other costs are
/// clamped to >= 0. Moving a length L over cells of mean cost c costs L (1 + w c). A copyable
/// value; reads are const and thread-safe.
class SearchCostMap {
 public:
  /// @throws std::out_of_range if the map lacks `config.cost_layer`.
  SearchCostMap(const common::GridLayers& map, const CostMapConfig& config);

  const common::GridGeometry& geometry() const { return geometry_; }
  const CostMapConfig& config() const { return config_; }

  /// Cost of cell (ix, iy), infinity if blocked. Precondition: geometry().Contains(ix, iy).
  double cost(int ix, int iy) const { return costs_(ix, iy); }

  /// Cost of the cell containing p_W (its nearest cell centre); infinity if that cell is blocked or
  /// p_W lies outside the grid.
  double CostAt(const Eigen::Vector2d& p_W) const;

  /// The smallest finite cell cost (0 if every cell is blocked): every metre costs at least
  /// 1 + w min_cost(), which makes L (1 + w min_cost()) an admissible heuristic.
  double min_cost() const { return min_cost_; }

  /// Cost of the straight segment a_W-b_W: L (1 + w c_mean), L = |b_W - a_W| [m] and c_mean the
  /// mean of CostAt at n + 1 evenly spaced samples including both ends, n = ceil(L / (resolution /
  /// 2)) (at most half a cell apart); infinity if any sample is blocked or outside the grid (or an
  /// end is not finite). Symmetric bit for bit: the samples are taken from the lexicographically
  /// smaller end. A*'s grid edges use the mean of their two cells instead; the two agree on a map
  /// of constant cost.
  double SegmentCost(const Eigen::Vector2d& a_W, const Eigen::Vector2d& b_W) const;

 private:
  common::GridGeometry geometry_;
  CostMapConfig config_;
  Eigen::MatrixXd costs_;  // per cell; infinity = blocked
  double min_cost_{0.0};
};

}  // namespace trav::planner
