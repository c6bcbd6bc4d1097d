#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/grid.h"

namespace trav::renders {

/// A polyline drawn as capsules between consecutive points (planned and driven paths).
struct Polyline {
  std::vector<Eigen::Vector3d> points_W;  ///< [m]
  Eigen::Vector4f rgba{1.0f, 0.2f, 0.1f, 1.0f};
  double width_m{0.04};  ///< [m]
};

/// Points drawn as small cubes (12 triangles each: cheap for a software renderer), one colour each
/// (LiDAR points, goals, obstacles).
struct ColoredPoints {
  Eigen::Matrix3Xf points_W;  ///< [m], one point per column
  Eigen::Matrix4Xf rgba;      ///< one colour per point (columns), or a single column for all
  double radius_m{0.03};      ///< half the side of a cube [m]
};

/// A coloured grid on the ground (traversability maps): each known cell is a flat box at its
/// height, coloured by its value from green (`value_min`) through yellow to red (`value_max`). NaN
/// cells are not drawn. Cells are subsampled so that at most `max_cells` are drawn.
struct GroundGrid {
  common::GridGeometry geometry{};
  Eigen::MatrixXf heights_m;  ///< cell heights [m], same shape as values
  Eigen::MatrixXf values;
  float value_min{0.0f};
  float value_max{1.0f};
  float alpha{0.6f};
  int max_cells{4000};
};

/// Where text goes on the frame.
enum class TextCorner { kTopLeft, kTopRight, kBottomLeft, kBottomRight };

/// A block of text drawn over the frame (lines separated by '\n').
struct TextLabel {
  std::string text;
  TextCorner corner{TextCorner::kTopLeft};
};

/// Everything drawn over the simulated scene in one frame. Later issues fill it with paths, maps,
/// LiDAR points and status text.
struct Overlay {
  std::vector<Polyline> polylines;
  std::vector<ColoredPoints> points;
  std::vector<GroundGrid> grids;
  std::vector<TextLabel> texts;
};

/// Colour of `value` on the green-yellow-red scale between `low` and `high` (clamped).
Eigen::Vector3f TraversabilityColor(float value, float low, float high);

}  // namespace trav::renders
