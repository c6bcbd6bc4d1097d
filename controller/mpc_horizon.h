#pragma once

#include <vector>

#include <Eigen/Core>

#include "controller/mpc.h"

namespace trav::controller {

/// The tracking MPC's horizon as a least-squares problem over its inputs u = (v_0, omega_0, v_1,
/// omega_1, ...) (MpcController minimises the sum of the squared residuals under its bounds).
///
/// The model: over each step of `step_s`, the achieved inputs approach the commanded ones by the
/// actuator's lag, then the unicycle moves by the midpoint rule. Per step k, kResidualsPerStep
/// residuals: the x, y and yaw errors of the state after the step against reference_states_W(k),
/// each scaled by the square root of its state weight; per input j (speed, yaw rate), its
/// deviation from reference_inputs(j, k), its rate against the step before (the first against
/// previous_command over one control period), and the smooth excess of that rate over the
/// acceleration limit, kRateLimitWeight (sqrt(rate^2 + 1e-6) - limit) where positive.
class MpcHorizon {
 public:
  /// Residuals per step: x, y, yaw; then per input its deviation, rate and rate-limit excess.
  static constexpr int kResidualsPerStep = 9;
  /// Weight of the rate-limit excess (per unit of acceleration beyond the limit).
  static constexpr double kRateLimitWeight = 30.0;

  const MpcConfig* config{nullptr};               ///< not owned; horizon N = config->horizon
  Eigen::Vector3d x0_W{Eigen::Vector3d::Zero()};  ///< x [m], y [m], yaw [rad] in W now
  /// The inputs achieved now (v [m/s], omega [rad/s]): where the actuator's lag starts from.
  Eigen::Vector2d achieved0{Eigen::Vector2d::Zero()};
  /// The command in force now (v [m/s], omega [rad/s]): the first rate's reference.
  Eigen::Vector2d previous_command{Eigen::Vector2d::Zero()};
  Eigen::Matrix3Xd reference_states_W;  ///< (x, y, yaw) after each step, 3 x N
  Eigen::Matrix2Xd reference_inputs;    ///< (v, omega) of each step, 2 x N

  int NumInputs() const { return 2 * config->horizon; }
  int NumResiduals() const { return kResidualsPerStep * config->horizon; }

  /// The states (x, y, yaw in W) after each step under inputs `u` (NumInputs values), 3 x N.
  Eigen::Matrix3Xd States(const double* u) const;

  /// Writes the NumResiduals residuals under inputs `u` (NumInputs values) and, unless
  /// `jacobian` is null, d residuals / d u there, row-major (NumResiduals rows of NumInputs), in
  /// closed form: the forward sensitivities of the same rollout, O(N^2), where automatic
  /// differentiation would carry a derivative per input through every step.
  void Evaluate(const double* u, double* residuals, double* jacobian = nullptr) const;

 private:
  // Writes the Jacobian at `u` from the rollout Evaluate has just stepped (speed_, mid_yaw_).
  void JacobianOfRollout(const double* u, double* jacobian) const;

  // The rollout's achieved speeds and midpoint yaws per step: storage kept between calls (no
  // allocation per evaluation once sized), so one horizon serves one thread.
  mutable std::vector<double> speed_, mid_yaw_;
};

}  // namespace trav::controller
