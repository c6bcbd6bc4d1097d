#pragma once

#include <utility>
#include <vector>

#include "common/pose.h"
#include "common/trajectory.h"
#include "controller/mpc.h"
#include "controller/trajectory_tracker.h"

namespace trav::controller {

/// Tracks a reference with the MPC in closed loop: solves at the control rate from the ground-truth
/// state, holds the command between solves, and records the tracking errors against the reference
/// at the same time (lateral and heading errors in the reference's frame).
class MpcTracker : public TrajectoryTracker {
 public:
  /// A tracker of `reference` (which may be empty until SetReference).
  explicit MpcTracker(const MpcConfig& config, common::Trajectory reference = {});

  /// Replaces the reference (a new plan); the MPC keeps its warm start and command history.
  void SetReference(common::Trajectory reference) override { reference_ = std::move(reference); }

  /// The command in force at the state's time (a new solve when a control period has passed).
  /// Precondition (checked): the reference is not empty.
  common::Twist2 Command(const common::RobotState& state) override;

  /// True if a call to Command at time t would solve (a control period has passed).
  bool SolveDue(double t_s) const override { return t_s + 1e-9 >= next_solve_s_; }

  /// Metrics over the solves so far.
  TrackingMetrics Metrics() const override;

  const common::Trajectory& reference() const override { return reference_; }
  /// Solves so far.
  int solves() const override { return static_cast<int>(solve_times_ms_.size()); }
  /// The MPC's predicted states of its latest solve (MpcController::predicted_states_W).
  const Eigen::Matrix3Xd& predicted_states_W() const override { return mpc_.predicted_states_W(); }

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
