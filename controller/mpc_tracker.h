#pragma once

#include <utility>
#include <vector>

#include "common/pose.h"
#include "common/trajectory.h"
#include "controller/mpc.h"

namespace trav::controller {

/// Tracking quality of a run, from every control tick.
struct TrackingMetrics {
  double rms_lateral_error_m{0.0};
  double max_lateral_error_m{0.0};
  double rms_heading_error_rad{0.0};
  double max_heading_error_rad{0.0};
  double rms_speed_error_m_s{0.0};
  double max_speed_error_m_s{0.0};
  double rms_acceleration_command_m_s2{0.0};        ///< control effort: RMS of dv_cmd/dt
  double rms_yaw_acceleration_command_rad_s2{0.0};  ///< control effort: RMS of domega_cmd/dt
  double solve_time_median_ms{0.0};
  double solve_time_p99_ms{0.0};
  double solve_time_max_ms{0.0};
  double iterations_mean{0.0};
  int solves{0};
  int failures{0};          ///< solves that fell back to braking
  int iteration_limits{0};  ///< solves stopped by the iteration cap or time budget
};

/// Tracks a reference with the MPC in closed loop: solves at the control rate from the ground-truth
/// state, holds the command between solves, and records the tracking errors against the reference
/// at the same time (lateral and heading errors in the reference's frame).
class MpcTracker {
 public:
  /// A tracker of `reference` (which may be empty until SetReference).
  explicit MpcTracker(const MpcConfig& config, common::Trajectory reference = {});

  /// Replaces the reference (a new plan); the MPC keeps its warm start and command history.
  void SetReference(common::Trajectory reference) { reference_ = std::move(reference); }

  /// The command in force at the state's time (a new solve when a control period has passed).
  /// Precondition (checked): the reference is not empty.
  common::Twist2 Command(const common::RobotState& state);

  /// True if a call to Command at time t would solve (a control period has passed).
  bool SolveDue(double t_s) const { return t_s + 1e-9 >= next_solve_s_; }

  /// Metrics over the solves so far.
  TrackingMetrics Metrics() const;

  const common::Trajectory& reference() const { return reference_; }
  /// Solves so far.
  int solves() const { return static_cast<int>(solve_times_ms_.size()); }
  /// The MPC's predicted states of its latest solve (MpcController::predicted_states_W).
  const Eigen::Matrix3Xd& predicted_states_W() const { return mpc_.predicted_states_W(); }

 private:
  MpcController mpc_;
  common::Trajectory reference_;
  double next_solve_s_{0.0};
  common::Twist2 command_{};
  std::vector<double> lateral_errors_, heading_errors_, speed_errors_;
  std::vector<double> accelerations_, yaw_accelerations_, solve_times_ms_;
  double iterations_{0.0};
  int failures_{0};
  int iteration_limits_{0};
};

}  // namespace trav::controller
