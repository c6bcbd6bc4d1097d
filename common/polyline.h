#pragma once

#include <vector>

#include <Eigen/Core>

namespace trav::common {

/// A planar polyline parameterised by arc length.
class Polyline {
 public:
  /// @throws std::invalid_argument if `points_W` is empty.
  explicit Polyline(std::vector<Eigen::Vector2d> points_W);

  /// Total length [m].
  double length() const { return arc_.back(); }

  /// The point at arc length s [m], clamped to [0, length()].
  Eigen::Vector2d PointAt(double s_m) const;

  /// Unit direction of travel at arc length s [m]: the chord over +-`half_span_m` around it
  /// (clamped to the ends); zero for a polyline of length zero.
  Eigen::Vector2d DirectionAt(double s_m, double half_span_m) const;

  const std::vector<Eigen::Vector2d>& points() const { return points_; }

 private:
  std::vector<Eigen::Vector2d> points_;
  std::vector<double> arc_;  // arc length at each point
};

}  // namespace trav::common
