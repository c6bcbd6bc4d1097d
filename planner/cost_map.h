#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/archive.h"
#include "common/check.h"
#include "common/enum_names.h"
#include "common/grid.h"

namespace trav::planner {

/// How the search costs treat cells whose cost is unknown (NaN).
enum class UnknownPolicy {
  kCost,     ///< traversable at `unknown_cost`
  kBlocked,  ///< never entered
};

/// The names of UnknownPolicy's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<UnknownPolicy>, 2> kUnknownPolicyNames{
    {{UnknownPolicy::kCost, "cost"}, {UnknownPolicy::kBlocked, "blocked"}}};
constexpr const auto& EnumNames(UnknownPolicy) { return kUnknownPolicyNames; }

/// Speed limits that the terrain sets (scenario section `planner.speed`), kept by the trajectory
/// optimiser through CostField::SpeedLimit. A cell's roughness is the map's layer of
/// common::Roughness: about half the height at the edge of a step, a stair or a curb, 0 on any
/// plane.
struct TerrainSpeedConfig {
  std::string roughness_layer{"roughness"};  ///< [m]; a map without it, or NaN: 0
  double unknown_m_s{1.0};  ///< over unknown cells (the ground ahead not yet seen) [m/s]
  double rough_m_s{1.1};    ///< over cells at least `rough_m` rough [m/s]
  double smooth_m{0.01};    ///< cells at most this rough set no limit [m]; linear up to rough_m
  double rough_m{0.03};     ///< [m], > smooth_m
  /// The speed where the terrain sets no limit [m/s]. Not a scenario key: the planner sets it to
  /// its own speed limit (NavigationPlannerConfig::SearchConfig).
  double open_m_s{1.5};
  /// A cell's limit holds for the base anywhere within this distance of it [m], so that it holds
  /// for every wheel. Not a scenario key: the planner sets it to the footprint's circumscribed
  /// radius.
  double reach_m{0.0};

  /// The keys of scenario section `planner.speed` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("unknown", &unknown_m_s, {0.05, 30});
    a->Field("rough", &rough_m_s, {0.05, 30});
    a->Field("smooth_roughness", &smooth_m, {0, 10});
    a->Field("rough_roughness", &rough_m, {0.001, 10});
  }

  /// The limit over a known cell of roughness `roughness_m` [m/s].
  double ForRoughness(double roughness_m) const;
};

/// The steepest ground the robot drives on (scenario section `planner.slope`). With the ground's
/// slope a, a heading at angle phi from the fall line has pitch tan a cos phi and roll
/// tan a sin phi (as tangents): the trajectory optimiser keeps both within the limits. The Scout
/// Mini's measured limits are 40 deg each (docs/navigation.md); the defaults, 89 deg, leave the
/// term out until the closed loop holds with them.
struct SlopeLimits {
  std::string elevation_layer{"elevation"};  ///< heights [m], for the slope and its direction
  double max_pitch_deg{89.0};                ///< climbing or descending [deg]
  double max_roll_deg{89.0};                 ///< across the slope [deg]

  /// The keys of scenario section `planner.slope` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("max_pitch", &max_pitch_deg, {1, 89});
    a->Field("max_roll", &max_roll_deg, {1, 89});
  }

  /// tan(max_pitch), tan(max_roll).
  Eigen::Vector2d Tangents() const;
  /// False when both limits are 89 deg (the largest allowed): the term is left out.
  bool Active() const { return max_pitch_deg < 89.0 || max_roll_deg < 89.0; }
};

/// How the robot crosses the steps it can climb (scenario section `planner.steps`). A step met
/// askew is climbed by one side first: the robot rolls onto it, straddles it and cannot turn from
/// there, or stalls at its foot (docs/navigation.md, "Steps crossed square"). The trajectory
/// optimiser keeps the heading within `max_angle` of the step's normal (either way) while the
/// footprint reaches a step cell. A step cell is one whose roughness (about half a step's height,
/// TerrainSpeedConfig) reads a step of at least `low_height`; its weight rises to 1 at
/// `full_height`, times the coherence of its direction. The step's normal is the dominant direction
/// of the roughness's gradient round the cell (the structure tensor): across the ridge that a
/// step's edge draws in the roughness. Cells beside lethal ones are no step cells (their roughness
/// measures the obstacle), nor are bumps and corners (no coherent direction).
struct StepCrossing {
  double max_angle_deg{15.0};  ///< from square [deg]; 90: no limit
  double low_height_m{0.10};   ///< steps lower than this are crossed at any angle [m]
  double full_height_m{0.14};  ///< the weight's full height [m], > low_height_m
  /// The step's limit holds for the base anywhere within this distance of a step cell [m]. Not a
  /// scenario key: the planner sets it to the footprint's circumscribed radius.
  double reach_m{0.0};

  /// The keys of scenario section `planner.steps` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("max_angle", &max_angle_deg, {0, 90});
    a->Field("low_height", &low_height_m, {0, 10});
    a->Field("full_height", &full_height_m, {0, 10});
  }

  /// False when `max_angle` is 90 deg: the term is left out.
  bool Active() const { return max_angle_deg < 90.0; }
  /// The weight of a cell of roughness `roughness_m` [m] in [0, 1]: 0 up to a step of
  /// `low_height`, 1 from `full_height`, linear between.
  double Weight(double roughness_m) const;
};

/// The height [m] of the step whose edge reads `roughness_m` in a map's roughness layer
/// (common::Roughness: about half the step's height).
inline double StepHeightOfRoughness(double roughness_m) { return 2.0 * roughness_m; }

/// How a traversability layer becomes search costs; the settings of A* (`AStarConfig`) and of the
/// sampling planners.
struct CostMapConfig {
  std::string cost_layer{"traversability"};  ///< layer of costs in [0, 1]
  double cost_weight{5.0};                   ///< w in the cost L (1 + w c), >= 0
  double lethal_threshold{0.8};              ///< cells at or above this cost are blocked
  UnknownPolicy unknown_policy{UnknownPolicy::kCost};
  double unknown_cost{0.5};  ///< cost of an unknown cell under kCost
  /// Cells whose centre lies closer than this to a known lethal cell (the distance between their
  /// boundaries, CostField) are blocked [m]. Not a scenario key: NavigationPlannerConfig sets it
  /// from the robot's footprint (its inscribed radius plus the smallest clearance).
  double inflation_radius_m{0.3};
  /// Cells closer than this (and not blocked) pay `band_cost` more, falling linearly to 0 at this
  /// distance [m] (the footprint's circumscribed radius plus the clearance): the search prefers
  /// the middle of passages, where the robot can turn. Not a scenario key; 0: no band.
  double band_radius_m{0.0};
  double band_cost{0.5};  ///< extra cost next to the blocked cells, in [0, 1]
  /// Where the robot may go [m]: CostMap reads every cell whose centre lies outside as lethal, so
  /// that the inflation keeps the whole footprint inside. The closed loop sets it to the world's
  /// extent: beyond the edge of a simulated world there is no ground to drive on, and the sensor,
  /// seeing nothing there, would leave it unknown and plannable. Not a scenario key; none: no
  /// limit.
  std::optional<Eigen::AlignedBox2d> operating_area_W;
  TerrainSpeedConfig speed;  ///< the terrain's speed limits (CostField::SpeedLimit)
  SlopeLimits slope;         ///< the steepest pitch and roll
  StepCrossing steps;        ///< how steps are crossed
  /// Whether the planners measure the distance to an obstacle's box within its lethal cell, where
  /// the map has one (CellExtents), instead of to the whole cell (docs/navigation.md, "The faces'
  /// boxes"): a 1.2 m door reads about 1.1 m wide instead of 0.8 m of free cells.
  bool obstacle_extents{true};
  /// The layers of CellExtents (x_low, x_high, y_low, y_high). Not a scenario key; a map without
  /// them has whole lethal cells.
  std::array<std::string, 4> extent_layers{
      {"face_x_low", "face_x_high", "face_y_low", "face_y_high"}};

  /// True if p_W lies in the operating area (anywhere without one).
  bool InOperatingArea(const Eigen::Vector2d& p_W) const {
    return !operating_area_W || operating_area_W->contains(p_W);
  }

  /// The keys of scenario section `planner.search` that configure the costs (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("cost_weight", &cost_weight, {0, 1000000.0});
    a->Field("lethal_threshold", &lethal_threshold, {0, 1});
    a->Enum("unknown_policy", &unknown_policy);
    a->Field("unknown_cost", &unknown_cost, {0, 1});
    a->Field("band_cost", &band_cost, {0, 1});
    a->Field("obstacle_extents", &obstacle_extents);
  }
};

/// Where the obstacle lies within each lethal cell, for the distances to it (ObstacleDistance): the
/// box of the points that showed it, as offsets from the cell's centre along x and y of W [m]
/// (mapping's layers `face_x_low` to `face_y_high`); NaN where unknown: the whole cell. Empty
/// matrices: every lethal cell whole.
struct CellExtents {
  Eigen::MatrixXf x_low, x_high, y_low, y_high;

  /// The extents in `map`'s layers `config.extent_layers` (x_low, x_high, y_low, y_high); empty
  /// unless `config.obstacle_extents` is set and the map has all four.
  static CellExtents Of(const common::GridLayers& map, const CostMapConfig& config);
  bool empty() const { return x_low.size() == 0; }
};

/// The lethal rule, the one every planner and safety check applies: a cell is lethal when its cost
/// is at or above `lethal_threshold`, or unknown (NaN) under UnknownPolicy::kBlocked.
bool IsLethal(float cost, const CostMapConfig& config);

class ObstacleMemory;

/// The per-cell cost c that every planner of this module pays, built once from a map: cells at or
/// above the lethal threshold are blocked (infinite cost) and so are the cells within the inflation
/// radius of them, cells within the band radius pay the band cost more (linearly less with the
/// distance), unknown cells follow the unknown policy, other costs are clamped to >= 0. Moving a
/// length L over cells of mean cost c costs L (1 + w c). A copyable value; reads are const and
/// thread-safe.
class SearchCostMap {
 public:
  /// @throws std::out_of_range if the map lacks `config.cost_layer`.
  SearchCostMap(const common::GridLayers& map, const CostMapConfig& config);

  /// From the cost layer itself (`layer` on `geometry`) and where the obstacles lie within the
  /// lethal cells (empty: the whole cells).
  SearchCostMap(const common::GridGeometry& geometry, const Eigen::MatrixXf& layer,
                const CostMapConfig& config, const CellExtents& extents = {});

  /// The same from the distances the inflation and the band are measured on, already computed:
  /// `known_obstacle_m` is LethalDistance(geometry, layer, config, extents, /*known_only=*/true);
  /// with what the robot remembers of the world beyond the map, if anything (memory()).
  SearchCostMap(const common::GridGeometry& geometry, const Eigen::MatrixXf& layer,
                const CostMapConfig& config, const Eigen::MatrixXd& known_obstacle_m,
                std::shared_ptr<const ObstacleMemory> memory = nullptr);

  const common::GridGeometry& geometry() const { return geometry_; }
  const CostMapConfig& config() const { return config_; }

  /// Cost of cell (ix, iy), infinity if blocked. Precondition (checked): geometry().Contains(ix,
  /// iy).
  double cost(int ix, int iy) const {
    TRAV_DEMAND(geometry_.Contains(ix, iy));
    return costs_(ix, iy);
  }

  /// Cost of the cell containing p_W (its nearest cell centre); infinity if that cell is blocked or
  /// p_W lies outside the grid.
  double CostAt(const Eigen::Vector2d& p_W) const;

  /// The smallest finite cell cost (0 if every cell is blocked): every metre costs at least
  /// 1 + w min_cost(), which makes L (1 + w min_cost()) an admissible heuristic.
  double min_cost() const { return min_cost_; }

  /// What the robot remembers of the obstacles beyond the map (and on it), for the ways out of the
  /// map (GridPlanner); null if nothing.
  const ObstacleMemory* memory() const { return memory_.get(); }

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
  std::shared_ptr<const ObstacleMemory> memory_;
};

class CostField;

/// One traversability map as every part of the planning stack reads it, built once per map
/// update: the search costs of A* (SearchCostMap), the smooth cost and distance fields of the
/// trajectory optimiser (CostField) and the lethal test of the navigator's safety checks, all
/// from one copy of the cost layer and one lethal rule (IsLethal). The search costs and the fields
/// are built on first use, on one distance transform of the lethal cells (LethalDistance) where
/// their lethal cells agree. Not thread-safe (the lazy parts).
class CostMap {
 public:
  /// The cells outside `config.operating_area_W` read as lethal (cost 1) for every part. The
  /// searches carry `memory`, what the robot remembers beyond the map (SearchCostMap::memory).
  /// @throws std::out_of_range if the map lacks `config.cost_layer`.
  CostMap(const common::GridLayers& map, const CostMapConfig& config,
          std::shared_ptr<const ObstacleMemory> memory = nullptr);
  ~CostMap();
  CostMap(CostMap&&) noexcept;
  CostMap& operator=(CostMap&&) noexcept;

  const common::GridGeometry& geometry() const { return geometry_; }
  const CostMapConfig& config() const { return config_; }

  /// True if p_W lies in a lethal cell (IsLethal); false outside the grid.
  bool LethalAt(const Eigen::Vector2d& p_W) const;

  /// The search costs with the inflation widened to the band radius: on these cells the robot
  /// can turn in place with the desired clearance (NavigationPlanner's first fallback).
  const SearchCostMap& wide_search() const;

  /// The search costs (lethal cells grown by the inflation radius, the band round them).
  const SearchCostMap& search() const;

  /// The cost, signed-distance and speed-limit fields.
  const CostField& field() const;

 private:
  common::GridGeometry geometry_;
  CostMapConfig config_;
  Eigen::MatrixXf layer_;
  Eigen::MatrixXf roughness_;  // empty when the map has no `config.speed.roughness_layer`
  Eigen::MatrixXf elevation_;  // empty when the map has no `config.slope.elevation_layer`
  CellExtents extents_;        // empty when the map has no `config.extent_layers`
  std::shared_ptr<const ObstacleMemory> memory_;  // for the searches
  // LethalDistance of the known lethal cells, shared by the searches and (where no unknown cell is
  // lethal) the field
  const Eigen::MatrixXd& known_obstacle_m() const;
  mutable std::unique_ptr<Eigen::MatrixXd> known_obstacle_m_;
  mutable std::unique_ptr<SearchCostMap> search_;
  mutable std::unique_ptr<SearchCostMap> wide_search_;
  mutable std::unique_ptr<CostField> field_;
};

}  // namespace trav::planner
