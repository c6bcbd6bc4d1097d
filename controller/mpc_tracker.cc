#include "controller/mpc_tracker.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"
#include "common/statistics.h"

namespace trav::controller {
namespace {

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

MpcTracker::MpcTracker(const MpcConfig& config, common::Trajectory reference)
    : mpc_(config), reference_(std::move(reference)) {}

common::Twist2 MpcTracker::Command(const common::RobotState& state) {
  TRAV_DEMAND(!reference_.empty());
  const double t = state.time_s;
  if (!SolveDue(t)) return command_;
  next_solve_s_ += mpc_.config().control_period_s;

  MpcState mpc_state;
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

  const MpcResult result = mpc_.Solve(mpc_state, reference_, t);
  const double period = mpc_.config().control_period_s;
  accelerations_.push_back((result.command.v - command_.v) / period);
  yaw_accelerations_.push_back((result.command.omega - command_.omega) / period);
  solve_times_ms_.push_back(1e3 * result.solve_time_s);
  iterations_ += result.iterations;
  failures_ += result.status == MpcStatus::kFailed;
  iteration_limits_ += result.status == MpcStatus::kIterationLimit;
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
  m.solve_time_median_ms = common::Quantile(solve_times_ms_, 0.5);
  m.solve_time_p99_ms = common::Quantile(solve_times_ms_, 0.99);
  m.solve_time_max_ms = common::Quantile(solve_times_ms_, 1.0);
  m.solves = static_cast<int>(solve_times_ms_.size());
  m.iterations_mean = m.solves > 0 ? iterations_ / m.solves : 0.0;
  m.failures = failures_;
  m.iteration_limits = iteration_limits_;
  return m;
}

}  // namespace trav::controller
