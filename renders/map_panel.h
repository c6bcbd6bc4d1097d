#pragma once

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/grid.h"
#include "renders/image.h"
#include "renders/overlay.h"

namespace trav::renders {

/// A path drawn on a map panel.
struct PanelPath {
  std::vector<Eigen::Vector2d> points_W;  ///< [m]
  Eigen::Vector3i rgb{255, 255, 255};
  int width_px{2};
};

/// A disc drawn on a map panel (moving obstacles, the goal, the robot).
struct PanelDisc {
  Eigen::Vector2d centre_W{Eigen::Vector2d::Zero()};  ///< [m]
  double radius_m{0.3};
  Eigen::Vector3i rgb{255, 255, 255};
  bool filled{true};
};

/// A rotated rectangle drawn on a map panel (the robot's footprint), with a tick from its centre
/// to the middle of its front side.
struct PanelBox {
  Eigen::Vector2d centre_W{Eigen::Vector2d::Zero()};  ///< [m]
  double yaw_rad{0.0};                                ///< of the box's x axis from W's x
  Eigen::Vector2d half_extents_m{0.3, 0.3};           ///< along the box's x and y [m]
  Eigen::Vector3i rgb{0, 0, 0};
};

/// What a map panel shows over the map's cells.
struct PanelOverlay {
  std::vector<PanelPath> paths;
  std::vector<Eigen::Vector2d> points_W;  ///< LiDAR points, drawn as single pixels [m]
  Eigen::Vector3i points_rgb{40, 120, 255};
  std::vector<PanelDisc> discs;
  std::vector<PanelBox> boxes;
};

/// A top-down picture of `layer` (values in [0, 1], NaN unknown) of `map`: the square of side
/// `span_m` centred on `centre_W` fills a `size_px` x `size_px` image (+x right, +y up), cells
/// coloured green through yellow to red as TraversabilityImage, unknown and outside cells grey,
/// then the overlay's paths, points, discs and boxes in that order.
Image DrawMapPanel(const common::GridLayers& map, const Eigen::MatrixXf& layer,
                   const Eigen::Vector2d& centre_W, double span_m, int size_px,
                   const PanelOverlay& overlay);

/// A symbol of a map panel's legend and what it stands for.
struct LegendEntry {
  enum class Symbol { kLine, kDisc, kDots, kBox };
  Symbol symbol{Symbol::kLine};
  Eigen::Vector3i rgb{255, 255, 255};
  std::string label;
};

/// The closed loop's panel beside the camera's view: `map` (a square image of `span_m` metres a
/// side, as DrawMapPanel draws it) at the top, and below it on a dark ground: the colour bar of
/// the cost scale (0 free, green, through yellow to 1 lethal, red) with ticks, the grey of unknown
/// cells, a scale bar of a round length (1, 2, 5, 10, ... m: the largest within a third of the
/// panel's width), the legend (two columns) and the `info` line (time, outcome). Texts are placed
/// for a font `line_px` pixels high whose lines are `text_width_px(line)` wide. The panel is
/// map.width wide and `height_px` high; rows below the map that the content does not need stay
/// dark. @throws std::invalid_argument if `height_px` < map.height.
Panel LayoutMapPanel(const Image& map, double span_m, int height_px,
                     const std::vector<LegendEntry>& legend, const std::string& info, int line_px,
                     const std::function<int(const std::string&)>& text_width_px);

/// The round length of a scale bar at most `max_m` long: 1, 2 or 5 times a power of ten [m].
double ScaleBarLength(double max_m);

/// Puts `right` to the right of `left` (heights must match). @throws std::invalid_argument.
Image SideBySide(const Image& left, const Image& right);

}  // namespace trav::renders
