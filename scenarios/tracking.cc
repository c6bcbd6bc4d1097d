#include "scenarios/tracking.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "common/input_error.h"
#include "common/input_file.h"
#include "scenarios/run_metrics.h"

namespace trav::scenarios {
namespace {

// Curve points every centimetre or closer, in the reference's own frame (start at the origin,
// heading +x).
std::vector<Eigen::Vector2d> ShapePoints(const TrackSettings& s) {
  std::vector<Eigen::Vector2d> points;
  switch (s.reference) {
    case ReferenceShape::kLine:
      for (double x = 0.0; x <= s.size_m + 1e-9; x += 0.01) points.emplace_back(x, 0.0);
      break;
    case ReferenceShape::kCircle:
      // counter-clockwise, centre on the left
      for (double a = 0.0; a <= 2.0 * M_PI + 1e-9; a += 0.01 / s.size_m) {
        points.emplace_back(s.size_m * std::sin(a), s.size_m * (1.0 - std::cos(a)));
      }
      break;
    case ReferenceShape::kFigureEight:
      // lemniscate of Gerono: two lobes through the start
      for (double a = 0.0; a <= 2.0 * M_PI + 1e-9; a += 0.002) {
        points.emplace_back(s.size_m * std::sin(a), s.size_m * std::sin(a) * std::cos(a));
      }
      break;
    case ReferenceShape::kSlalom:
      for (double x = 0.0; x <= s.size_m + 1e-9; x += 0.01) {
        points.emplace_back(x, s.amplitude_m * std::sin(2.0 * M_PI * x / s.wavelength_m));
      }
      break;
    case ReferenceShape::kFile:
      break;
  }
  return points;
}

common::Trajectory LoadReference(const std::string& path) {
  std::istringstream file(common::ReadInputFile(path, "reference trajectory"));
  std::string line;
  std::getline(file, line);
  if (line.rfind("t,x,y,yaw,v,omega", 0) != 0) {
    throw common::InputError(path, "line 1",
                             "expected the header 't,x,y,yaw,v,omega' (is this a trajectory?)");
  }
  std::vector<common::TrajectoryPoint> points;
  for (int number = 2; std::getline(file, line); ++number) {
    if (line.empty()) continue;
    std::stringstream row(line);
    double values[6];
    bool ok = true;
    for (int k = 0; k < 6 && ok; ++k) {
      char comma = ',';
      ok = static_cast<bool>(row >> values[k]) && (k == 5 || (row >> comma && comma == ','));
    }
    if (!ok || !std::all_of(values, values + 6, [](double v) { return std::isfinite(v); }) ||
        (!points.empty() && values[0] <= points.back().t_s)) {
      throw common::InputError(path, "line " + std::to_string(number),
                               "expected 6 finite numbers with increasing t, got " +
                                   common::QuotedExcerpt(line));
    }
    common::TrajectoryPoint p;
    p.t_s = values[0];
    p.position_W = Eigen::Vector2d(values[1], values[2]);
    p.yaw = values[3];
    p.v = values[4];
    p.omega = values[5];
    points.push_back(p);
  }
  if (points.size() < 2) throw common::InputError(path, "track.file", "needs at least 2 points");
  return common::Trajectory(std::move(points));
}

double Rms(const std::vector<double>& values) {
  if (values.empty()) return 0.0;
  double sum = 0.0;
  for (double v : values) sum += v * v;
  return std::sqrt(sum / static_cast<double>(values.size()));
}

double MaxAbs(const std::vector<double>& values) {
  double largest = 0.0;
  for (double v : values) largest = std::max(largest, std::abs(v));
  return largest;
}

}  // namespace

common::Trajectory BuildReference(const TrackSettings& settings, const common::Pose2& start_W) {
  if (settings.reference == ReferenceShape::kFile) return LoadReference(settings.file);
  // place the shape at the start pose, its initial tangent along the start heading
  std::vector<Eigen::Vector2d> path = ShapePoints(settings);
  const Eigen::Vector2d tangent = path[std::min<std::size_t>(5, path.size() - 1)] - path.front();
  const Eigen::Rotation2Dd R_WS(start_W.yaw - std::atan2(tangent.y(), tangent.x()));
  for (Eigen::Vector2d& p : path) p = start_W.position + R_WS * p;
  return common::TrajectoryAlongPath(path, settings.speed_m_s, settings.acceleration_m_s2);
}

MpcTracker::MpcTracker(const controller::MpcConfig& config, common::Trajectory reference)
    : mpc_(config), reference_(std::move(reference)) {}

common::Twist2 MpcTracker::Command(const common::RobotState& state) {
  const double t = state.time_s;
  if (!SolveDue(t)) return command_;
  next_solve_s_ += mpc_.config().control_period_s;

  controller::MpcState mpc_state;
  mpc_state.position_W = state.X_WB.translation().head<2>();
  const Eigen::Vector3d forward = state.X_WB.linear().col(0);
  mpc_state.yaw = std::atan2(forward.y(), forward.x());
  mpc_state.v = state.v_WB_B.x();
  mpc_state.omega = state.w_WB_B.z();

  // errors against the reference now, in the reference's frame
  const common::TrajectoryPoint r = reference_.Sample(t);
  const Eigen::Vector2d e = mpc_state.position_W - r.position_W;
  lateral_errors_.push_back(-std::sin(r.yaw) * e.x() + std::cos(r.yaw) * e.y());
  heading_errors_.push_back(std::remainder(mpc_state.yaw - r.yaw, 2.0 * M_PI));
  speed_errors_.push_back(mpc_state.v - r.v);

  const controller::MpcResult result = mpc_.Solve(mpc_state, reference_, t);
  const double period = mpc_.config().control_period_s;
  accelerations_.push_back((result.command.v - command_.v) / period);
  yaw_accelerations_.push_back((result.command.omega - command_.omega) / period);
  solve_times_ms_.push_back(1e3 * result.solve_time_s);
  iterations_ += result.iterations;
  failures_ += result.status == controller::MpcStatus::kFailed;
  iteration_limits_ += result.status == controller::MpcStatus::kIterationLimit;
  command_ = result.command;
  return command_;
}

TrackingMetrics MpcTracker::Metrics() const {
  TrackingMetrics m;
  m.rms_lateral_error_m = Rms(lateral_errors_);
  m.max_lateral_error_m = MaxAbs(lateral_errors_);
  m.rms_heading_error_rad = Rms(heading_errors_);
  m.max_heading_error_rad = MaxAbs(heading_errors_);
  m.rms_speed_error_m_s = Rms(speed_errors_);
  m.max_speed_error_m_s = MaxAbs(speed_errors_);
  m.rms_acceleration_command_m_s2 = Rms(accelerations_);
  m.rms_yaw_acceleration_command_rad_s2 = Rms(yaw_accelerations_);
  m.solve_time_median_ms = Quantile(solve_times_ms_, 0.5);
  m.solve_time_p99_ms = Quantile(solve_times_ms_, 0.99);
  m.solve_time_max_ms = Quantile(solve_times_ms_, 1.0);
  m.solves = static_cast<int>(solve_times_ms_.size());
  m.iterations_mean = m.solves > 0 ? iterations_ / m.solves : 0.0;
  m.failures = failures_;
  m.iteration_limits = iteration_limits_;
  return m;
}

}  // namespace trav::scenarios
