#pragma once

#include <Eigen/Core>

#include "common/pose.h"
#include "common/trajectory.h"

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

/// Tracks a reference trajectory in closed loop: what the navigator and the track mode drive. The
/// MPC tracker implements it; a user's controller implements it to plug in by name
/// (`controller.method`, scenarios/run/plugins.h).
class TrajectoryTracker {
 public:
  virtual ~TrajectoryTracker() = default;

  /// Replaces the reference (a new plan).
  virtual void SetReference(common::Trajectory reference) = 0;

  /// The command in force at the state's time: a new one when a control period has passed (the
  /// true state of the base; its time is simulation time). Precondition: a reference is set.
  virtual common::Twist2 Command(const common::RobotState& state) = 0;

  /// True if a call to Command at time t [s] would compute a new command.
  virtual bool SolveDue(double t_s) const = 0;

  /// Tracking quality over the commands so far (fields a controller does not measure stay 0).
  virtual TrackingMetrics Metrics() const = 0;

  /// The reference being tracked.
  virtual const common::Trajectory& reference() const = 0;

  /// New commands computed so far.
  virtual int solves() const = 0;

  /// The states (x [m], y [m], yaw [rad] in W) the latest command predicts over its horizon, one
  /// column per step; empty for a controller that predicts none.
  virtual const Eigen::Matrix3Xd& predicted_states_W() const = 0;
};

}  // namespace trav::controller
