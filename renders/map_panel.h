#pragma once

#include <vector>

#include <Eigen/Core>

#include "common/grid.h"
#include "renders/image.h"

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

/// What a map panel shows over the map's cells.
struct PanelOverlay {
  std::vector<PanelPath> paths;
  std::vector<Eigen::Vector2d> points_W;  ///< LiDAR points, drawn as single pixels [m]
  Eigen::Vector3i points_rgb{40, 120, 255};
  std::vector<PanelDisc> discs;
};

/// A top-down picture of `layer` (values in [0, 1], NaN unknown) of `map`: the square of side
/// `span_m` centred on `centre_W` fills a `size_px` x `size_px` image (+x right, +y up), cells
/// coloured green through yellow to red as TraversabilityImage, unknown and outside cells grey,
/// then the overlay's paths, points and discs in that order.
Image DrawMapPanel(const common::GridLayers& map, const Eigen::MatrixXf& layer,
                   const Eigen::Vector2d& centre_W, double span_m, int size_px,
                   const PanelOverlay& overlay);

/// Puts `right` to the right of `left` (heights must match). @throws std::invalid_argument.
Image SideBySide(const Image& left, const Image& right);

}  // namespace trav::renders
