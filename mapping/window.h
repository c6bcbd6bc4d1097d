#pragma once

#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "common/grid.h"
#include "common/point_cloud.h"
#include "common/scratch.h"
#include "mapping/fsgp_config.h"
#include "mapping/traversability_mapper.h"

namespace trav::mapping {

/// Crops LiDAR frames to the window around the robot, reusing its storage between frames (no
/// allocation once a frame of the size has been seen).
class WindowCrop {
 public:
  /// The valid points of `points_W` in the square window of side `window_m` around the robot, no
  /// higher than `max_height_above_m` above its base and, if finite, no higher than
  /// `max_height_above_ground_m` above the local ground (walls and trunks keep only their foot):
  /// the higher of the lowest point of their 1 m column and the plane fitted through the lowest
  /// points of that column and its eight neighbours (its slope clamped at 45 deg), at the point.
  /// The plane keeps slopes whole: ground of slope a rises up to sqrt(2) tan(a) m across a
  /// column, more than the crop height above 12 deg. Counts the input, the NaN or infinite points
  /// dropped and the points kept in `result`.
  void Crop(const common::PointCloud& points_W, const Eigen::Vector3d& p_WB, double window_m,
            double max_height_above_m, double max_height_above_ground_m, MapUpdateResult* result);

  /// Drops from the last crop's window every point that stands more than `max_above_floor_m`,
  /// plus the crop's ground plane's rise across a cell's diagonal, above the lowest point its
  /// cell of `map` ever showed (layer `floor`, which ObstacleMarker::Mark keeps; cells without
  /// one keep their points): with the crop height, the local ground of Crop is then at most the
  /// cell's floor. Within the sensor's blind zone a column's lowest points can be a wall's, a
  /// beam's height up its face, or the top of a low wall that a robot pitched up sees without
  /// the ground before it. Infinite `max_above_floor_m`: nothing dropped.
  void KeepNearFloor(const common::GridLayers& map, double max_above_floor_m);

  /// The last crop's points, one per column [m].
  common::ScratchMatrix<float, 3>::ConstView window() const { return window_.view(); }
  /// The last crop's window before the ground crop (every point no higher than
  /// `max_height_above_m` above the base).
  common::ScratchMatrix<float, 3>::ConstView below_robot() const { return below_robot_.view(); }

  /// The last crop's ground gradient (dz/dx, dz/dy) at p_W: its plane's in p_W's column (a point
  /// off the window: the nearest column's); zero where no plane was fitted or after a crop
  /// without the ground crop.
  Eigen::Vector2f GroundGradient(const Eigen::Vector2d& p_W) const;

 private:
  static constexpr double kColumn_m = 1.0;  // the columns' side

  // Index of the column of (x_m, y_m) in the last crop's window (clamped to it: the points on
  // its far borders fall in the last columns).
  std::size_t ColumnOf(double x_m, double y_m) const;
  // The plane z = c0 + c1 (x - x_B) + c2 (y - y_B) through the lowest points of column (cx, cy)
  // and its neighbours, by least squares; c0 = -infinity where they do not fix a plane.
  Eigen::Vector3f GroundPlane(int cx, int cy) const;

  common::ScratchMatrix<float, 3> window_, below_robot_;
  // The last ground crop's window: its centre (the base), half its side and columns along a side.
  Eigen::Vector3d p_WB_{Eigen::Vector3d::Zero()};
  double half_window_m_{0.0};
  int columns_{0};
  // Per 1 m column: its lowest point (z infinite without points) and GroundPlane; empty after a
  // crop without the ground crop.
  std::vector<Eigen::Vector3f> column_lowest_;
  std::vector<Eigen::Vector3f> column_plane_;
};

/// Marks the faces that a ground crop removed in a map's obstacle layer, reusing its storage
/// between frames.
class ObstacleMarker {
 public:
  /// Per cell of `g` between `low` and `high` (inclusive), indexed from `low`: 1 where the highest
  /// point of the cell lies more than `min_span_m` above the lowest point of its 3 x 3 cell
  /// neighbourhood (a vertical face: wall, trunk, box side, even where the face's points are
  /// sparse), or more than `max_step_m` (> 0; 0 disables the test) above the highest point of a
  /// side neighbour with points, or of the cell's own lowest point where no point of the
  /// neighbourhood lies more than 2 cm lower (a step the robot cannot climb, however low: a
  /// platform, a curb, a low wall whose foot the sensor does not see from close by), or more than
  /// `max_bump_m` (> 0; 0 disables the test) above the highest points of both cells one or two
  /// cells away on either side along x, y or a diagonal (a bump the robot would straddle: rubble
  /// between its wheels; a curb has ground as high on one side), 0 where none holds, NaN where
  /// the cell has no point. With `floor` (the map's layer `floor`, indexed by the cells of `g`:
  /// the lowest point each cell showed before), a cell whose highest point stands more than
  /// `min_span_m` above its floor is a face too (a jamb's end, a few centimetres of which fill a
  /// cell whose ground now lies in the sensor's blind zone, beside cells without points), and a
  /// face cell whose lowest point stands above its floor shows no ground: all its points are the
  /// face's (extents()). With `ground` (the crop of these points), every
  /// comparison is made above the crop's ground plane at the cell (WindowCrop::GroundGradient): a
  /// neighbour's point counts as risen by the plane's rise between the two cells' centres, and a
  /// cell's own span less the plane's rise across its diagonal. Without it, ground of slope a rises
  /// up to 2 sqrt(2) resolution tan(a) across the neighbourhood, resolution tan(a) from a side
  /// neighbour and sqrt(2) resolution tan(a) within a cell: at 0.2 m cells slopes steeper than
  /// about 28 deg read as faces; with it, slopes up to the robot's 40 deg do not. Valid until the
  /// next call, as roughness().
  common::ScratchMatrix<float>::ConstView Cells(const Eigen::Ref<const Eigen::Matrix3Xf>& points_W,
                                                const common::GridGeometry& g,
                                                const Eigen::Vector2i& low,
                                                const Eigen::Vector2i& high, double min_span_m,
                                                double max_step_m, double max_bump_m,
                                                const WindowCrop* ground = nullptr,
                                                const Eigen::MatrixXf* floor = nullptr);

  /// Per cell of the last Cells call: common::Roughness of the highest points (NaN where the cell
  /// has no point; a neighbour without points is left out) [m].
  common::ScratchMatrix<float>::ConstView roughness() const { return roughness_.const_view(); }

  /// Per cell of the last Cells call, column ix + nx iy (cell (ix, iy) of nx along x, indexed from
  /// `low`): where its highest point stands more than `min_span_m` above its neighbourhood's
  /// lowest (a face taller than the crop: a wall, a trunk, a box), the box of its points more than
  /// 5 cm above its own lowest point and the ground plane's rise across it (the face's, not the
  /// ground's at its foot), as the offsets x_low, x_high, y_low, y_high from the cell's centre
  /// along x and y of W [m]; NaN elsewhere: a lower step's points (its top seen at grazing angles,
  /// its face in the sensor's blind zone once the robot is near) do not bound it.
  common::ScratchMatrix<float, 4>::ConstView extents() const { return extents_.const_view(); }

  /// Per cell of the last Cells call, 1 where a drop hides: the cell has no point, and lies on a
  /// line of cells (along x, y or a diagonal) from an edge to the first cell with points beyond,
  /// which lies no farther than `area.drop_gap_m` from the edge, its highest point more than
  /// `area.max_drop_m` below the edge's lowest and lower on average more steeply than
  /// `area.drop_slope_deg`, with at least one more cell without points between; both measured
  /// below the ground falling on beyond the edge as it falls toward it (from the farthest cell of
  /// ground on the line up to 1 m before the edge; at most at the drop slope's rate): a hillside
  /// the robot drives down is no drop where the gaps between its points open. The edge is a
  /// cell with points that is no face (Cells 0), its lowest point no more than `area.max_step_m`
  /// above the base at p_WB (ground the robot may stand on, not the top of a box), and so is the
  /// cell behind it on the line, its lowest point within `area.max_step_m` of the edge's (seen
  /// ground up to the edge, not a lone point on a trunk). Ground beyond an edge lower than the
  /// robot drives down, with no point showing how it gets there: the cliff under an edge, which no
  /// beam from above reaches. 0 elsewhere; nothing with `area.drop_gap_m` 0. Valid until the next
  /// call, as Cells.
  common::ScratchMatrix<std::uint8_t>::ConstView Drops(const common::GridGeometry& g,
                                                       const MapArea& area,
                                                       const Eigen::Vector3d& p_WB);

  /// Marks the faces the ground crop removed and the steps (Cells of `crop`'s window before the
  /// ground crop, above its ground plane, with the crop height `area.max_height_above_ground_m`
  /// and the step `area.max_step_m`) in layer `obstacle` of `map` between `low` and `high`: the
  /// latest observation of a cell decides, so a cell seen free again clears (but a face shown for
  /// `area.obstacle_memory_s` or longer only once the cell has shown free for
  /// `area.obstacle_clear_s`; layer `free_since`), and a face cell stamps layer `obstacle_seen`
  /// with `t_s` (and `obstacle_since`, where it was no face before); layer
  /// `roughness` takes roughness() where a cell has points. Layer `floor` keeps the lowest point
  /// each cell ever showed; a cell whose highest point stands more than `area.max_step_m` (> 0)
  /// plus the ground plane's rise across it above its floor, or whose floor stands that much above
  /// a side neighbour's, is a step (a low wall whose foot the frame does not show, a face whose
  /// foot its cell never showed); a cell whose lowest point stands more than half the crop
  /// height above it shows no ground and is no evidence of free space (its obstacle stays), or a
  /// face if its highest point stands more than the crop height above it. The Drops are marked as
  /// faces. Layers `face_x_low` to `face_y_high` keep the union of a face cell's extents() over
  /// the frames of its unbroken run as a face that have one (NaN, the whole cell, until one has: a
  /// step's, a drop's); a cell seen free has none, a forgotten face keeps its extent. A face
  /// cell within `area.blind_radius_m` of the base at p_WB that points showed for less than
  /// `area.obstacle_memory_s` (> 0), and that no point has shown for longer than that since, is
  /// forgotten: its obstacle becomes unknown, and its cost too if the mapper has never scored it.
  /// Then sets layer `traversability` to 1 on the obstacle mask closed by one cell, within
  /// `margin_cells` of the window (at least the cells whose cost the mapper rewrote). The obstacle
  /// layer FSGP-BGK and the baselines share.
  void Mark(const WindowCrop& crop, const Eigen::Vector2i& low, const Eigen::Vector2i& high,
            const MapArea& area, const Eigen::Vector3d& p_WB, double t_s, int margin_cells,
            common::GridLayers* map);

 private:
  // The closing (dilation, then erosion) of mask_ by the 3 x 3 cell square, into closed_.
  void CloseMask();
  // Cells' extents_: per cell (from `low`), the box of its points above face_floor_.
  void BoxFaces(const Eigen::Ref<const Eigen::Matrix3Xf>& points_W, const common::GridGeometry& g,
                const Eigen::Vector2i& low);

  common::ScratchMatrix<float> lowest_, highest_, cells_, roughness_, face_floor_;
  common::ScratchMatrix<float, 4> extents_;
  common::ScratchMatrix<std::uint8_t> mask_, dilated_, closed_, drops_;
  std::vector<Eigen::Vector2i> gap_;          // Drops: the cells without points along one line
  std::vector<Eigen::Vector2i> point_cells_;  // Cells: each point's cell from `low`, -1 outside
};

/// The first and last cell (ix, iy) of the window around the robot on the grid `g`.
std::pair<Eigen::Vector2i, Eigen::Vector2i> WindowCells(const common::GridGeometry& g,
                                                        const Eigen::Vector3d& p_WB,
                                                        double window_m);

}  // namespace trav::mapping
