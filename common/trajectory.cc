#include "common/trajectory.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/polyline.h"

namespace trav::common {

Trajectory::Trajectory(std::vector<TrajectoryPoint> points) : points_(std::move(points)) {
  if (points_.empty()) throw std::invalid_argument("Trajectory: no points");
  for (std::size_t i = 1; i < points_.size(); ++i) {
    if (!(points_[i].t_s > points_[i - 1].t_s)) {
      throw std::invalid_argument("Trajectory: times must strictly increase (point " +
                                  std::to_string(i) + ")");
    }
  }
}

TrajectoryPoint Trajectory::Sample(double t_s) const {
  TRAV_DEMAND(!points_.empty());
  if (t_s <= points_.front().t_s) return points_.front();
  if (t_s >= points_.back().t_s) return points_.back();
  const auto after = std::upper_bound(points_.begin(), points_.end(), t_s,
                                      [](double t, const TrajectoryPoint& p) { return t < p.t_s; });
  const TrajectoryPoint& b = *after;
  const TrajectoryPoint& a = *(after - 1);
  const double s = (t_s - a.t_s) / (b.t_s - a.t_s);
  TrajectoryPoint p;
  p.t_s = t_s;
  p.position_W = a.position_W + s * (b.position_W - a.position_W);
  p.yaw = a.yaw + s * (b.yaw - a.yaw);
  p.v = a.v + s * (b.v - a.v);
  p.omega = a.omega + s * (b.omega - a.omega);
  p.acceleration = a.acceleration + s * (b.acceleration - a.acceleration);
  return p;
}

Trajectory TrajectoryAlongPath(const std::vector<Eigen::Vector2d>& path_W, double speed,
                               double acceleration, double dt_s) {
  if (path_W.size() < 2 || speed <= 0.0 || acceleration <= 0.0 || dt_s <= 0.0) {
    throw std::invalid_argument(
        "TrajectoryAlongPath: needs 2 points and positive speed, acceleration, dt");
  }
  const Polyline path(path_W);
  const double length = path.length();

  // trapezoidal speed profile (triangular if the path is too short to reach the speed)
  const double peak = std::min(speed, std::sqrt(acceleration * length));
  const double ramp_s = peak / acceleration;
  const double ramp_length = 0.5 * peak * ramp_s;
  const double cruise_s = (length - 2.0 * ramp_length) / peak;
  const double duration = 2.0 * ramp_s + cruise_s;
  auto distance_and_speed = [&](double t) -> std::pair<double, double> {
    if (t < ramp_s) return {0.5 * acceleration * t * t, acceleration * t};
    if (t < ramp_s + cruise_s) return {ramp_length + peak * (t - ramp_s), peak};
    const double left = std::max(0.0, duration - t);
    return {length - 0.5 * acceleration * left * left, acceleration * left};
  };

  const int steps = static_cast<int>(std::ceil(duration / dt_s));
  std::vector<TrajectoryPoint> points(static_cast<std::size_t>(steps) + 1);
  const double tangent_step = std::min(0.02, 0.25 * length);
  double previous_yaw = 0.0;
  for (int k = 0; k <= steps; ++k) {
    TrajectoryPoint& p = points[static_cast<std::size_t>(k)];
    p.t_s = std::min(k * dt_s, duration);
    const auto [s, v] = distance_and_speed(p.t_s);
    p.position_W = path.PointAt(s);
    p.v = v;
    p.acceleration =
        p.t_s < ramp_s ? acceleration : (p.t_s < ramp_s + cruise_s ? 0.0 : -acceleration);
    // tangent by a central difference along the arc; yaw kept continuous
    const Eigen::Vector2d tangent = path.DirectionAt(s, tangent_step);
    double yaw = std::atan2(tangent.y(), tangent.x());
    if (k > 0) yaw = previous_yaw + std::remainder(yaw - previous_yaw, 2.0 * M_PI);
    p.yaw = yaw;
    previous_yaw = yaw;
  }
  // yaw rate from the samples (central differences)
  for (std::size_t k = 0; k < points.size(); ++k) {
    const std::size_t lo = k == 0 ? 0 : k - 1;
    const std::size_t hi = std::min(points.size() - 1, k + 1);
    const double span = points[hi].t_s - points[lo].t_s;
    points[k].omega = span > 0.0 ? (points[hi].yaw - points[lo].yaw) / span : 0.0;
  }
  // the last sample may repeat the duration when it divides evenly: keep times strictly increasing
  if (points.size() >= 2 && !(points.back().t_s > points[points.size() - 2].t_s)) points.pop_back();
  return Trajectory(std::move(points));
}

}  // namespace trav::common
