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

// Whether the search grows the lethal cells (by the inflation or the band).
bool Grows(const CostMapConfig& config) {
  return config.inflation_radius_m > 0.0 || config.band_radius_m > 0.0;
}

// Per-cell cost for the search (infinity = blocked), with the inflation and the band applied round
// the known lethal cells (unknown cells blocked by the policy are not grown) by their distances
// `known_obstacle_m` (LethalDistance, known only; not read unless Grows(config)).
Eigen::MatrixXd SearchCosts(const common::GridGeometry& g, const Eigen::MatrixXf& layer,
                            const CostMapConfig& config, const Eigen::MatrixXd& known_obstacle_m) {
  Eigen::MatrixXd costs(g.num_x, g.num_y);
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      const float c = layer(ix, iy);
      if (IsLethal(c, config)) {
        costs(ix, iy) = kInfinity;
      } else {
        costs(ix, iy) = std::isnan(c) ? config.unknown_cost : std::max(0.0f, c);
      }
    }
  }
  if (!Grows(config)) return costs;
  // the distance from a cell's centre to the nearest lethal cell's obstacle, as CostField
  // measures it: the search admits exactly the cells where the field's distance allows the robot
  const double band = config.band_radius_m - config.inflation_radius_m;
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      const double distance_m = known_obstacle_m(ix, iy);
      if (!std::isfinite(costs(ix, iy)) || !std::isfinite(distance_m)) continue;
      if (distance_m < config.inflation_radius_m) {
        costs(ix, iy) = kInfinity;
      } else if (band > 0.0 && distance_m < config.band_radius_m) {
        costs(ix, iy) += config.band_cost * (config.band_radius_m - distance_m) / band;
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

CellExtents CellExtents::Of(const common::GridLayers& map, const CostMapConfig& config) {
  CellExtents extents;
  const std::array<std::string, 4>& layers = config.extent_layers;
  if (config.obstacle_extents &&
      std::all_of(layers.begin(), layers.end(),
                  [&](const std::string& layer) { return map.Has(layer); })) {
    extents.x_low = map.Layer(layers[0]);
    extents.x_high = map.Layer(layers[1]);
    extents.y_low = map.Layer(layers[2]);
    extents.y_high = map.Layer(layers[3]);
  }
  return extents;
}

SearchCostMap::SearchCostMap(const common::GridLayers& map, const CostMapConfig& config)
    : SearchCostMap(map.geometry(), map.Layer(config.cost_layer), config,
                    CellExtents::Of(map, config)) {}

SearchCostMap::SearchCostMap(const common::GridGeometry& geometry, const Eigen::MatrixXf& layer,
                             const CostMapConfig& config, const CellExtents& extents)
    : SearchCostMap(geometry, layer, config,
                    Grows(config) ? LethalDistance(geometry, layer, config, extents, true)
                                  : Eigen::MatrixXd()) {}

SearchCostMap::SearchCostMap(const common::GridGeometry& geometry, const Eigen::MatrixXf& layer,
                             const CostMapConfig& config, const Eigen::MatrixXd& known_obstacle_m,
                             std::shared_ptr<const ObstacleMemory> memory)
    : geometry_(geometry),
      config_(config),
      costs_(SearchCosts(geometry, layer, config, known_obstacle_m)),
      min_cost_(MinFiniteCost(costs_)),
      memory_(std::move(memory)) {}

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

double TerrainSpeedConfig::ForRoughness(double roughness_m) const {
  if (!(roughness_m > smooth_m)) return open_m_s;
  if (roughness_m >= rough_m) return std::min(open_m_s, rough_m_s);
  const double fraction = (roughness_m - smooth_m) / (rough_m - smooth_m);
  return std::min(open_m_s, open_m_s + fraction * (rough_m_s - open_m_s));
}

Eigen::Vector2d SlopeLimits::Tangents() const {
  constexpr double kDegToRad = M_PI / 180.0;
  return {std::tan(max_pitch_deg * kDegToRad), std::tan(max_roll_deg * kDegToRad)};
}

double StepCrossing::Weight(double roughness_m) const {
  const double height = StepHeightOfRoughness(roughness_m);
  if (!(height > low_height_m)) return 0.0;
  return std::min(1.0, (height - low_height_m) / (full_height_m - low_height_m));
}

CostMap::CostMap(const common::GridLayers& map, const CostMapConfig& config,
                 std::shared_ptr<const ObstacleMemory> memory)
    : geometry_(map.geometry()),
      config_(config),
      layer_(map.Layer(config.cost_layer)),
      memory_(std::move(memory)) {
  if (map.Has(config.speed.roughness_layer)) roughness_ = map.Layer(config.speed.roughness_layer);
  if (map.Has(config.slope.elevation_layer)) elevation_ = map.Layer(config.slope.elevation_layer);
  extents_ = CellExtents::Of(map, config);
  if (!config.operating_area_W) return;
  for (int ix = 0; ix < geometry_.num_x; ++ix) {
    for (int iy = 0; iy < geometry_.num_y; ++iy) {
      if (config.InOperatingArea(geometry_.CellCenter(ix, iy))) continue;
      layer_(ix, iy) = 1.0f;
      if (!extents_.empty()) extents_.x_low(ix, iy) = std::numeric_limits<float>::quiet_NaN();
    }
  }
}

CostMap::~CostMap() = default;
CostMap::CostMap(CostMap&&) noexcept = default;
CostMap& CostMap::operator=(CostMap&&) noexcept = default;

bool CostMap::LethalAt(const Eigen::Vector2d& p_W) const {
  const std::optional<Eigen::Vector2i> cell = geometry_.CellIndex(p_W);
  return cell && IsLethal(layer_(cell->x(), cell->y()), config_);
}

const Eigen::MatrixXd& CostMap::known_obstacle_m() const {
  if (!known_obstacle_m_) {
    known_obstacle_m_ = std::make_unique<Eigen::MatrixXd>(
        LethalDistance(geometry_, layer_, config_, extents_, /*known_only=*/true));
  }
  return *known_obstacle_m_;
}

const SearchCostMap& CostMap::search() const {
  if (!search_) {
    search_ =
        std::make_unique<SearchCostMap>(geometry_, layer_, config_, known_obstacle_m(), memory_);
  }
  return *search_;
}

const SearchCostMap& CostMap::wide_search() const {
  if (!wide_search_) {
    CostMapConfig wide = config_;
    wide.inflation_radius_m = std::max(config_.inflation_radius_m, config_.band_radius_m);
    wide_search_ =
        std::make_unique<SearchCostMap>(geometry_, layer_, wide, known_obstacle_m(), memory_);
  }
  return *wide_search_;
}

const CostField& CostMap::field() const {
  if (!field_) {
    const Eigen::MatrixXf* roughness_m = roughness_.size() > 0 ? &roughness_ : nullptr;
    const Eigen::MatrixXf* elevation_m = elevation_.size() > 0 ? &elevation_ : nullptr;
    // the field's lethal cells are the searches' unless unknown cells are lethal
    const bool unknown_lethal =
        config_.unknown_policy == UnknownPolicy::kBlocked && layer_.array().isNaN().any();
    field_ = unknown_lethal
                 ? std::make_unique<CostField>(geometry_, layer_, config_, roughness_m, elevation_m,
                                               extents_)
                 : std::make_unique<CostField>(geometry_, layer_, config_, roughness_m, elevation_m,
                                               known_obstacle_m(), extents_);
  }
  return *field_;
}

}  // namespace trav::planner
