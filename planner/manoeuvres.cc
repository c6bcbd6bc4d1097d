#include "planner/manoeuvres.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "common/check.h"
#include "common/input_error.h"

namespace trav::planner {
namespace {

// The angle from `from` to `to` wrapped into (-pi, pi] [rad].
double TurnAngle(double from, double to) { return std::remainder(to - from, 2.0 * M_PI); }

// Appends samples of a constant-rate motion from `from` (a copy: it may be an element of `points`)
// over `duration_s`, `v` forward and `omega` about z: the end is included, `from` is not.
void AppendMotion(common::TrajectoryPoint from, double duration_s, double v, double omega,
                  double step_s, std::vector<common::TrajectoryPoint>* points) {
  if (duration_s < 1e-6) return;  // shorter motions would not advance the time stamps
  const int steps = std::max(1, static_cast<int>(std::ceil(duration_s / step_s - 1e-9)));
  for (int k = 1; k <= steps; ++k) {
    const double t = duration_s * k / steps;
    common::TrajectoryPoint p;
    p.t_s = from.t_s + t;
    p.yaw = from.yaw + omega * t;
    p.position_W =
        from.position_W + v * t * Eigen::Vector2d(std::cos(from.yaw), std::sin(from.yaw));
    p.v = k == steps ? 0.0 : v;
    p.omega = k == steps ? 0.0 : omega;
    points->push_back(p);
  }
}

// Appends a turn in place from the last point of `points` to `heading` (the shorter way round).
void AppendTurn(double heading, const FallbackConfig& config,
                std::vector<common::TrajectoryPoint>* points) {
  const double turn = TurnAngle(points->back().yaw, heading);
  AppendMotion(points->back(), std::abs(turn) / config.creep_yaw_rate_rad_s, 0.0,
               std::copysign(config.creep_yaw_rate_rad_s, turn), config.output_step_s, points);
}

// Appends a turn in place to `heading`, then a straight drive to target_W at `creep_speed`, forward
// (direction 1) or backward (-1) along it.
void AppendLeg(double heading, const Eigen::Vector2d& target_W, double direction,
               const FallbackConfig& config, std::vector<common::TrajectoryPoint>* points) {
  AppendTurn(heading, config, points);
  AppendMotion(points->back(),
               (target_W - points->back().position_W).norm() / config.creep_speed_m_s,
               direction * config.creep_speed_m_s, 0.0, config.output_step_s, points);
}

// The start at rest: the first point of every manoeuvre.
std::vector<common::TrajectoryPoint> AtRest(const common::TrajectoryPoint& start) {
  common::TrajectoryPoint at = start;
  at.v = at.omega = at.acceleration = 0.0;
  return {at};
}

}  // namespace

void ValidateFallbackConfig(const FallbackConfig& c) {
  using common::RequireValue;
  RequireValue(c.creep_speed_m_s > 0.0, "creep_speed", c.creep_speed_m_s, "must be > 0");
  RequireValue(c.creep_yaw_rate_rad_s > 0.0, "creep_yaw_rate", c.creep_yaw_rate_rad_s,
               "must be > 0");
  RequireValue(c.back_out_distance_m > 0.0, "back_out_distance", c.back_out_distance_m,
               "must be > 0");
  RequireValue(c.search_reach_m > 0.0, "search_reach", c.search_reach_m, "must be > 0");
  RequireValue(c.search_expansions >= 0, "search_expansions", c.search_expansions, "must be >= 0");
  RequireValue(c.output_step_s > 0.0, "output_step", c.output_step_s, "must be > 0");
}

common::Trajectory StopFrom(const common::TrajectoryPoint& start, const FallbackConfig& config) {
  TRAV_DEMAND(config.braking_m_s2 > 0.0);
  std::vector<common::TrajectoryPoint> points = {start};
  const double duration_s = std::abs(start.v) / config.braking_m_s2;
  if (duration_s >= 1e-6) {
    // v and omega fall linearly to zero: the yaw integrated exactly, the position by the midpoint
    // rule, one output step at a time
    const int steps = std::max(1, static_cast<int>(std::ceil(duration_s / config.output_step_s)));
    const double deceleration = std::copysign(config.braking_m_s2, start.v);
    auto yaw_at = [&](double t) {
      return start.yaw + start.omega * (t - 0.5 * t * t / duration_s);
    };
    for (int k = 1; k <= steps; ++k) {
      const double t0 = duration_s * (k - 1) / steps;
      const double t1 = duration_s * k / steps;
      const double mid = 0.5 * (t0 + t1);
      common::TrajectoryPoint p = points.back();
      p.t_s = start.t_s + t1;
      p.position_W += (t1 - t0) * (start.v - deceleration * mid) *
                      Eigen::Vector2d(std::cos(yaw_at(mid)), std::sin(yaw_at(mid)));
      p.yaw = yaw_at(t1);
      p.v = start.v - deceleration * t1;
      p.omega = start.omega * (1.0 - t1 / duration_s);
      p.acceleration = -deceleration;
      points.push_back(p);
    }
  }
  common::TrajectoryPoint& rest = points.back();
  rest.v = rest.omega = rest.acceleration = 0.0;
  return common::Trajectory(std::move(points));
}

std::optional<common::Trajectory> StopAlong(const common::Trajectory& path,
                                            const common::TrajectoryPoint& start,
                                            const FallbackConfig& config) {
  TRAV_DEMAND(config.braking_m_s2 > 0.0);
  const double speed = std::abs(start.v);
  if (path.empty() || speed < 1e-9) return std::nullopt;
  const double duration_s = speed / config.braking_m_s2;
  const double stop_m = 0.5 * speed * duration_s;
  // the distance the path's positions cover from start.t_s, as (time, distance) at a quarter of
  // the output step, up to the stop's
  const double fine_s = 0.25 * config.output_step_s;
  std::vector<std::pair<double, double>> covered = {{start.t_s, 0.0}};
  Eigen::Vector2d previous_W = path.Sample(start.t_s).position_W;
  while (covered.back().second < stop_m) {
    const double t = covered.back().first;
    if (t >= path.end_time()) return std::nullopt;
    const double next = std::min(t + fine_s, path.end_time());
    const Eigen::Vector2d p_W = path.Sample(next).position_W;
    covered.emplace_back(next, covered.back().second + (p_W - previous_W).norm());
    previous_W = p_W;
  }
  const int steps = std::max(1, static_cast<int>(std::ceil(duration_s / config.output_step_s)));
  const double deceleration = std::copysign(config.braking_m_s2, start.v);
  std::vector<common::TrajectoryPoint> points = {start};
  std::size_t segment = 1;
  for (int k = 1; k <= steps; ++k) {
    const double tau = duration_s * k / steps;
    const double distance_m = speed * tau - 0.5 * config.braking_m_s2 * tau * tau;
    while (segment + 1 < covered.size() && covered[segment].second < distance_m) ++segment;
    const auto [t0, d0] = covered[segment - 1];
    const auto [t1, d1] = covered[segment];
    const double t =
        d1 > d0 ? t0 + (t1 - t0) * std::clamp((distance_m - d0) / (d1 - d0), 0.0, 1.0) : t1;
    const common::TrajectoryPoint on = path.Sample(t);
    common::TrajectoryPoint p;
    p.t_s = start.t_s + tau;
    p.position_W = on.position_W;
    p.yaw = on.yaw;
    p.v = start.v - deceleration * tau;
    p.omega = std::abs(on.v) > 1e-9 ? on.omega * p.v / on.v : 0.0;
    p.acceleration = -deceleration;
    points.push_back(p);
  }
  common::TrajectoryPoint& rest = points.back();
  rest.v = rest.omega = rest.acceleration = 0.0;
  return common::Trajectory(std::move(points));
}

common::Trajectory CreepAlong(const common::TrajectoryPoint& start,
                              const std::vector<Eigen::Vector2d>& waypoints_W, bool reverse,
                              const FallbackConfig& config) {
  std::vector<common::TrajectoryPoint> points = AtRest(start);
  const double direction = reverse ? -1.0 : 1.0;
  for (std::size_t i = 1; i < waypoints_W.size(); ++i) {
    const Eigen::Vector2d segment = waypoints_W[i] - points.back().position_W;
    const double length = segment.norm();
    if (length < 1e-6) continue;
    AppendLeg(std::atan2(direction * segment.y(), direction * segment.x()), waypoints_W[i],
              direction, config, &points);
  }
  return common::Trajectory(std::move(points));
}

common::Trajectory CreepThrough(const common::TrajectoryPoint& start,
                                const std::vector<common::Pose2>& poses,
                                const FallbackConfig& config) {
  std::vector<common::TrajectoryPoint> points = AtRest(start);
  for (const common::Pose2& pose : poses) {
    const Eigen::Vector2d heading(std::cos(pose.yaw), std::sin(pose.yaw));
    const double along = (pose.position - points.back().position_W).dot(heading);
    AppendLeg(pose.yaw, pose.position, along < 0.0 ? -1.0 : 1.0, config, &points);
  }
  return common::Trajectory(std::move(points));
}

common::Trajectory TurnInPlace(const common::TrajectoryPoint& start, double yaw,
                               const FallbackConfig& config) {
  std::vector<common::TrajectoryPoint> points = AtRest(start);
  AppendTurn(yaw, config, &points);
  return common::Trajectory(std::move(points));
}

common::Trajectory SaferStop(const CostField& field, const common::TrajectoryPoint& start,
                             const common::Trajectory* followed,
                             const std::vector<Eigen::Vector2d>& body_points_B,
                             const FallbackConfig& config) {
  common::Trajectory stop = StopFrom(start, config);
  if (followed == nullptr) return stop;
  std::optional<common::Trajectory> along = StopAlong(*followed, start, config);
  if (along &&
      SmallestGap(field, *along, body_points_B) > SmallestGap(field, stop, body_points_B)) {
    return std::move(*along);
  }
  return stop;
}

double SmallestGap(const CostField& field, const common::Trajectory& trajectory,
                   const std::vector<Eigen::Vector2d>& body_points_B) {
  double smallest = std::numeric_limits<double>::infinity();
  for (const common::TrajectoryPoint& p : trajectory.points()) {
    smallest = std::min(smallest, FootprintDistance(field, p.position_W, p.yaw, body_points_B));
  }
  return smallest;
}

bool KeepsClear(const CostField& field, const common::Trajectory& trajectory,
                const std::vector<Eigen::Vector2d>& body_points_B, double min_clearance_m) {
  const std::vector<common::TrajectoryPoint>& points = trajectory.points();
  if (points.empty()) return true;
  const double floor_m =
      std::min(min_clearance_m, FootprintDistance(field, points.front().position_W,
                                                  points.front().yaw, body_points_B)) -
      1e-9;
  return SmallestGap(field, trajectory, body_points_B) >= floor_m;
}

}  // namespace trav::planner
