#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/footprint.h"
#include "common/grid.h"
#include "planner/cost_map.h"

namespace trav::planner {

/// A value of a field and its gradient in W, both bilinear in the cell values.
struct FieldSample {
  double value{0.0};
  Eigen::Vector2d gradient_W{Eigen::Vector2d::Zero()};  ///< per metre
  /// d^2 value / dx dy, per square metre (the only second derivative of a bilinear cell that is
  /// not 0).
  double cross_derivative{0.0};
};

/// The traversability map as smooth fields for trajectory optimisation: the cost c in [0, 1], the
/// signed distance to the nearest lethal cell [m] (positive outside, negative inside) and the
/// terrain's speed limit [m/s], all interpolated bilinearly with their gradients, as uneven_planner
/// and DDR-opt do (a nearest-cell lookup would have zero gradient almost everywhere). Cells are
/// read as A* reads them: lethal by IsLethal, unknown cells of cost `unknown_cost` when not lethal;
/// A*'s inflation does not apply (clearance is the optimiser's own term). Points outside the grid
/// take the border's values with zero gradient.
class CostField {
 public:
  /// @throws std::out_of_range if the map lacks `config.cost_layer`.
  CostField(const common::GridLayers& map, const CostMapConfig& config);

  /// From the cost layer itself (`layer` on `geometry`) and, unless null, the roughness and the
  /// elevation of the same cells (TerrainSpeedConfig, SlopeLimits; without them the speed limit
  /// knows no roughness and no slope is limited) and where the obstacles lie within the lethal
  /// cells (empty: the whole cells).
  CostField(const common::GridGeometry& geometry, const Eigen::MatrixXf& layer,
            const CostMapConfig& config, const Eigen::MatrixXf* roughness_m = nullptr,
            const Eigen::MatrixXf* elevation_m = nullptr, const CellExtents& extents = {});

  /// The same from the signed distance's outside part, already computed: `outside_m` is
  /// LethalDistance(geometry, layer, config, extents, /*known_only=*/false).
  CostField(const common::GridGeometry& geometry, const Eigen::MatrixXf& layer,
            const CostMapConfig& config, const Eigen::MatrixXf* roughness_m,
            const Eigen::MatrixXf* elevation_m, const Eigen::MatrixXd& outside_m,
            const CellExtents& extents);

  /// Cost at p_W.
  FieldSample Cost(const Eigen::Vector2d& p_W) const { return Interpolate(cost_, p_W); }

  /// Signed distance to the nearest lethal cell at p_W [m], bilinear in ObstacleDistance at the
  /// cell centres (a lethal cell whose centre lies inside its obstacle: minus the distance from its
  /// centre to the nearest cell that is not lethal, less half a cell); a map without lethal cells
  /// reads as `kFarDistance` everywhere. Where the four centres around p_W lie within
  /// kExactBand_m of the faces whose boxes CellExtents gives, the Euclidean distance from p_W to
  /// the nearest of their nearest boxes with its gradient, where that is the smaller:
  /// interpolated between centres, the distance to a box's corner reads up to half a cell too far
  /// (a cone's chord lies above it), and the optimiser took door jambs' ends by their last few
  /// centimetres. Inside such a box, at most 0. Lethal cells without a box (steps, bumps, drops,
  /// unknown cells, and every cell without extents) keep the interpolation.
  FieldSample Distance(const Eigen::Vector2d& p_W) const;

  /// The terrain's speed limit at p_W [m/s] (TerrainSpeedConfig): `unknown_m_s` over unknown
  /// cells, over known ones TerrainSpeedConfig::ForRoughness of the cell's roughness (NaN: 0),
  /// never above `open_m_s`; each cell holds the smallest limit within `reach_m` of it.
  FieldSample SpeedLimit(const Eigen::Vector2d& p_W) const {
    return Interpolate(speed_limit_, p_W);
  }

  /// The ground's height at p_W [m] from the map's `config.slope.elevation_layer`, its gradient
  /// (the slope's tangent along x and y) and cross derivative; NaN where a cell around p_W is
  /// unknown, the map has no such layer or the slope limits are off (SlopeLimits::Active). Within
  /// `kGroundReach_m` of lethal cells, where the mapped elevation climbs the obstacle's foot, the
  /// heights are filled in from the cells beyond that reach (the nearest one's, then smoothed
  /// toward Laplace's solution), so that near obstacles the slope is the surrounding ground's.
  FieldSample Elevation(const Eigen::Vector2d& p_W) const { return Interpolate(elevation_, p_W); }

  /// The slope limits of `config.slope`: the tangents of the largest pitch and roll.
  const Eigen::Vector2d& max_pitch_roll_tangents() const { return max_pitch_roll_tangents_; }

  /// The weight w in [0, 1] of the steps within `config.steps.reach_m` of p_W
  /// (StepCrossing::Weight, times the coherence of their direction): 0 away from steps, where the
  /// map has no roughness layer or the term is off (StepCrossing::Active). Each cell holds the
  /// strongest step cell within the reach.
  FieldSample StepWeight(const Eigen::Vector2d& p_W) const {
    return Interpolate(step_weight_, p_W);
  }
  /// That step's normal phi as w (cos 2 phi, sin 2 phi) (the doubled angle: a normal and its
  /// opposite are one direction of crossing), each component with its gradient.
  std::array<FieldSample, 2> StepAxis(const Eigen::Vector2d& p_W) const {
    return {Interpolate(step_axis_x_, p_W), Interpolate(step_axis_y_, p_W)};
  }
  /// True if StepWeight is positive anywhere (a step cell on the map).
  bool HasSteps() const { return has_steps_; }
  /// cos(2 max_angle) of `config.steps`: a heading theta is within the limit where
  /// cos 2 (theta - phi) >= this.
  double step_cos_twice_max_angle() const { return step_cos_twice_max_angle_; }

  /// The speed where the terrain sets no limit [m/s] (TerrainSpeedConfig::open_m_s).
  double open_speed_m_s() const { return open_speed_m_s_; }

  const common::GridGeometry& geometry() const { return geometry_; }

  /// Distance reported when there is no lethal cell [m].
  static constexpr double kFarDistance = 1.0e3;
  /// Distance from lethal cells within which the mapped elevation is not read as ground [m].
  static constexpr double kGroundReach_m = 1.0;
  /// Distance from the faces' boxes within which Distance is the Euclidean distance to them [m]:
  /// beyond the optimiser's clearance by more than a cell's diagonal (0.15 m and 0.28 m on the
  /// default map; there the interpolation reads at most 1 cm too far).
  static constexpr double kExactBand_m = 0.5;

 private:
  FieldSample Interpolate(const Eigen::MatrixXd& layer, const Eigen::Vector2d& p_W) const;
  /// Sets nearest_obstacle_ and obstacles_ from the lethal cells and their extents.
  void FindNearestObstacles(const Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>& lethal,
                            const CellExtents& extents);

  common::GridGeometry geometry_;
  Eigen::MatrixXd cost_;
  Eigen::MatrixXd distance_;
  Eigen::MatrixXd speed_limit_;
  Eigen::MatrixXd elevation_;
  Eigen::MatrixXd step_weight_;
  Eigen::MatrixXd step_axis_x_;
  Eigen::MatrixXd step_axis_y_;
  // per cell whose centre lies within kExactBand_m of the obstacles, the index in obstacles_ of
  // the face's box nearest to it within that band (a face's cell whose box holds its centre: its
  // own); -1 elsewhere and in lethal cells without a box
  Eigen::MatrixXi nearest_obstacle_;
  std::vector<Eigen::AlignedBox2d> obstacles_;
  Eigen::Vector2d max_pitch_roll_tangents_{Eigen::Vector2d::Zero()};
  double open_speed_m_s_{0.0};
  double step_cos_twice_max_angle_{-1.0};
  bool has_steps_{false};
};

/// The footprint's boundary points in B (common::Footprint::BoundaryPoints_B) at which the planners
/// measure its distance to lethal cells on a field of `resolution_m` cells, keeping `clearance_m`:
/// at most a cell apart (no lethal cell fits between two of them) and at most half the clearance,
/// since an obstacle's box may end anywhere within its cell (a box's corner between two points
/// lies within a quarter of the clearance of one), but not closer than a quarter of a cell.
std::vector<Eigen::Vector2d> BodyPoints_B(const common::Footprint& footprint, double resolution_m,
                                          double clearance_m);

/// The smallest signed distance to lethal cells (CostField::Distance) of the robot's body points
/// `body_points_B` (BodyPoints_B) with its base at position_W and heading
/// `yaw` [m]; infinity without points.
double FootprintDistance(const CostField& field, const Eigen::Vector2d& position_W, double yaw,
                         const std::vector<Eigen::Vector2d>& body_points_B);

/// The smallest of `values` within `radius` cells of each cell (the cells (dx, dy) with
/// dx^2 + dy^2 <= radius^2: an erosion by a disc), by one pass along x per half-width of the disc
/// and one along y. 0 or less: `values` itself.
Eigen::MatrixXd MinimumWithinDisc(const Eigen::MatrixXd& values, int radius);

/// Distance [m] from each cell's centre to the obstacles of the cells where `lethal` is true. With
/// `extents` empty: the distance to the nearest lethal cell's centre less half a cell,
/// which is the distance to its boundary along x or y. With them: within kExactReach_m, the
/// Euclidean distance to the nearest of the lethal cells' obstacles, each the box `extents` gives
/// within its cell or the whole cell where that is NaN; farther, as without them. A lethal cell
/// reads 0 where its centre lies inside its obstacle, else its distance as any other cell's (a
/// cell holding a wall's last few centimetres). Infinity everywhere if no cell is lethal.
Eigen::MatrixXd ObstacleDistance(const common::GridGeometry& g,
                                 const Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>& lethal,
                                 const CellExtents& extents);

/// ObstacleDistance of the cells of the cost layer `layer` (on `g`) that IsLethal reads lethal;
/// with `known_only`, without the unknown cells the unknown policy blocks (A*'s inflation and band
/// grow known obstacles only). Without unknown lethal cells the two are the same.
Eigen::MatrixXd LethalDistance(const common::GridGeometry& g, const Eigen::MatrixXf& layer,
                               const CostMapConfig& config, const CellExtents& extents,
                               bool known_only);

/// How far from lethal cells ObstacleDistance measures to their boxes [m]: beyond the optimiser's
/// clearance and A*'s band round the footprint's circumscribed radius (0.57 m for the Scout Mini).
inline constexpr double kExactReach_m = 0.8;

/// Euclidean distance [cells] from each cell centre to the nearest cell where `mask` is true, exact
/// (Felzenszwalb and Huttenlocher, "Distance Transforms of Sampled Functions", 2012: two passes of
/// the 1-D lower-envelope transform). Infinity everywhere if no cell is set.
Eigen::MatrixXd DistanceTransform(const Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>& mask);

}  // namespace trav::planner
