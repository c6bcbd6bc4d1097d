#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/grid.h"
#include "renders/image.h"

namespace trav::renders {

/// A polyline drawn as capsules between consecutive points (planned and driven paths).
struct Polyline {
  std::vector<Eigen::Vector3d> points_W;  ///< [m]
  Eigen::Vector4f rgba{1.0f, 0.2f, 0.1f, 1.0f};
  double width_m{0.04};  ///< [m]
};

/// Points drawn as round screen-space dots (LiDAR points, goals), one colour each; translucent
/// colours blend (older LiDAR frames fading out).
struct ColoredPoints {
  Eigen::Matrix3Xf points_W;  ///< [m], one point per column
  Eigen::Matrix4Xf rgba;      ///< one colour per point (columns), or a single column for all
  float size_px{3.0f};        ///< diameter of a dot [pixels]
};

/// A coloured grid draped on the ground (traversability maps): a translucent mesh through the
/// known cells, each coloured by its value from green (`value_min`) through yellow to red
/// (`value_max`), `lift_m` above its height. NaN cells (value or height) are not drawn.
struct GroundGrid {
  common::GridGeometry geometry{};
  Eigen::MatrixXf heights_m;  ///< cell heights [m], same shape as values
  Eigen::MatrixXf values;
  float value_min{0.0f};
  float value_max{1.0f};
  float alpha{0.6f};
  double lift_m{0.03};  ///< [m] above the heights, so the terrain does not hide it
};

/// A pedestrian drawn as a simple articulated figure (head, torso, arms and legs): the legs and
/// arms swing with the gait phase.
struct Walker {
  /// The figure's frame: origin halfway up the figure above its feet, x the walking direction.
  Eigen::Isometry3d X_WO{Eigen::Isometry3d::Identity()};
  double height_m{1.7};  ///< [m]
  /// Phase of the gait [rad]: the left leg is furthest forward at pi/2, the right at 3 pi/2.
  double gait_phase_rad{0.0};
  Eigen::Vector4f rgba{0.95f, 0.55f, 0.1f, 1.0f};  ///< clothes
};

/// A hand cart: a box on four wheels with a push handle at its back (-x).
struct Cart {
  /// The cart's frame: origin at the centre of its bounding box, x the direction of travel.
  Eigen::Isometry3d X_WO{Eigen::Isometry3d::Identity()};
  Eigen::Vector3d half_extents_m{0.4, 0.3, 0.5};  ///< of the bounding box [m]
  Eigen::Vector4f rgba{0.2f, 0.45f, 0.85f, 1.0f};
};

/// Where text goes on the frame.
enum class TextCorner { kTopLeft, kTopRight, kBottomLeft, kBottomRight, kCenter };

/// A block of text drawn over the frame (lines separated by '\n'). Centred text is large, on a
/// dark card (the end card of a run).
struct TextLabel {
  std::string text;
  TextCorner corner{TextCorner::kTopLeft};
};

/// Text at a pixel of a panel.
struct PanelText {
  std::string text;
  Eigen::Vector2i top_left_px{0, 0};  ///< the text's top-left corner (column, row; row 0 at top)
  Eigen::Vector3f rgb{1.0f, 1.0f, 1.0f};
};

/// A picture drawn to the right of the camera's view in the same frame (the map panel), with
/// text labels drawn by the renderer's font.
struct Panel {
  Image image;  ///< RenderConfig::panel_width x RenderConfig::height, or empty: no panel
  std::vector<PanelText> texts;
};

/// Everything drawn over the simulated scene in one frame.
struct Overlay {
  std::vector<Polyline> polylines;
  std::vector<ColoredPoints> points;
  std::vector<GroundGrid> grids;
  std::vector<TextLabel> texts;
  std::vector<Walker> walkers;
  std::vector<Cart> carts;
  /// The simulation's movers (indices) whose own geoms are not drawn (they are drawn as walkers
  /// or carts instead).
  std::vector<int> hidden_movers;
  Panel panel;
};

/// Colour of `value` on the green-yellow-red scale between `low` and `high` (clamped).
Eigen::Vector3f TraversabilityColor(float value, float low, float high);

}  // namespace trav::renders
