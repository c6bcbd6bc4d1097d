#include "common/polyline.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace trav::common {

Polyline::Polyline(std::vector<Eigen::Vector2d> points_W) : points_(std::move(points_W)) {
  if (points_.empty()) throw std::invalid_argument("Polyline: no points");
  arc_.assign(points_.size(), 0.0);
  for (std::size_t i = 1; i < points_.size(); ++i) {
    arc_[i] = arc_[i - 1] + (points_[i] - points_[i - 1]).norm();
  }
}

Eigen::Vector2d Polyline::PointAt(double s_m) const {
  if (points_.size() == 1) return points_.front();
  const double s = std::clamp(s_m, 0.0, length());
  const auto after = std::upper_bound(arc_.begin(), arc_.end(), s);
  const std::size_t j =
      std::min<std::size_t>(std::max<std::ptrdiff_t>(1, after - arc_.begin()), arc_.size() - 1);
  const double span = arc_[j] - arc_[j - 1];
  const double f = span > 0.0 ? (s - arc_[j - 1]) / span : 0.0;
  return points_[j - 1] + f * (points_[j] - points_[j - 1]);
}

Eigen::Vector2d Polyline::DirectionAt(double s_m, double half_span_m) const {
  const Eigen::Vector2d chord = PointAt(s_m + half_span_m) - PointAt(s_m - half_span_m);
  const double norm = chord.norm();
  return norm > 0.0 ? Eigen::Vector2d(chord / norm) : Eigen::Vector2d::Zero();
}

}  // namespace trav::common
