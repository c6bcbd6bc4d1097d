#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/archive.h"
#include "common/pose.h"
#include "common/trajectory.h"

namespace trav::controller {

/// Weights, limits and solver settings of the tracking MPC (scenario key `controller.mpc`).
struct MpcConfig {
  int horizon{30};                ///< prediction steps N, in [2, 200]
  double step_s{0.05};            ///< prediction step [s], in [0.005, 0.2]: 30 x 0.05 = 1.5 s ahead
  double control_period_s{0.02};  ///< time between solves and command updates [s] (50 Hz)
  /// Tracking weights on the x, y [1/m^2] and yaw [1/rad^2] errors at every predicted step, >= 0.
  Eigen::Vector3d state_weights{40.0, 40.0, 4.0};
  /// Weights on (v - v_ref, omega - omega_ref), >= 0: small, the reference carries the
  /// feed-forward.
  Eigen::Vector2d input_weights{0.1, 0.1};
  /// Weights on the input rates (dv/dt, domega/dt), >= 0: smooth commands.
  Eigen::Vector2d rate_weights{0.02, 0.005};
  double max_speed_m_s{3.0};                ///< forward limit [m/s], > 0
  double min_speed_m_s{-1.0};               ///< reverse limit [m/s], <= 0
  double max_yaw_rate_rad_s{2.5};           ///< [rad/s], > 0
  double max_acceleration_m_s2{2.0};        ///< |dv/dt| limit [m/s^2], > 0
  double max_yaw_acceleration_rad_s2{6.0};  ///< |domega/dt| limit [rad/s^2], > 0
  /// First-order lag of the actuation (0: none) [s], >= 0: the model predicts the achieved (v,
  /// omega) approaching the command with this time constant.
  double actuator_time_constant_s{0.0};
  /// Solver iteration cap, in [1, 1000]. The only cap: a wall-time budget would make a run
  /// depend on the machine's load.
  int max_iterations{15};

  /// The keys of scenario section `controller.mpc` (common/archive.h); the control period is the
  /// section above's `rate`.
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("horizon", &horizon, {1, 200});
    a->Field("step", &step_s, {0.005, 1});
    a->Field("state_weights", &state_weights, {0, 1000000.0});
    a->Field("input_weights", &input_weights, {0, 1000000.0});
    a->Field("rate_weights", &rate_weights, {0, 1000000.0});
    a->Field("max_speed", &max_speed_m_s, {0.01, 30});
    a->Field("min_speed", &min_speed_m_s, {-30, 0});
    a->Field("max_yaw_rate", &max_yaw_rate_rad_s, {0.01, 30});
    a->Field("max_acceleration", &max_acceleration_m_s2, {0.01, 100});
    a->Field("max_yaw_acceleration", &max_yaw_acceleration_rad_s2, {0.01, 100});
    a->Field("actuator_time_constant", &actuator_time_constant_s, {0, 10});
    a->Field("max_iterations", &max_iterations, {1, 1000});
  }
};

/// Checks a config. @throws common::InputError naming the key (relative: "horizon") and value.
void ValidateMpcConfig(const MpcConfig& config);

/// The version of the Ceres solver library the MPC uses ("2.1.0").
std::string CeresVersion();

/// The robot's planar state as the MPC sees it.
struct MpcState {
  Eigen::Vector2d position_W{Eigen::Vector2d::Zero()};  ///< [m]
  double yaw{0.0};                                      ///< [rad]
  double v{0.0};      ///< measured forward speed [m/s] (used by the lag model)
  double omega{0.0};  ///< measured yaw rate [rad/s] (used by the lag model)
};

/// How a solve ended.
enum class MpcStatus {
  kSolved,          ///< converged
  kIterationLimit,  ///< stopped by the iteration cap: the improved inputs are used
  kFailed,          ///< no usable solution: the command is the safe fallback (braking)
};

/// Result of one solve.
struct MpcResult {
  MpcStatus status{MpcStatus::kSolved};
  common::Twist2 command{};  ///< within the bounds and the rate limits from the previous command
  int iterations{0};
  double solve_time_s{0.0};
  double cost{0.0};  ///< final cost of the horizon
};

/// Model-predictive tracking control of a unicycle (x, y, yaw; inputs v, omega; optional
/// first-order actuator lag) on a horizon of N steps, solved as a bounded nonlinear least-squares
/// problem with Ceres (single shooting: the inputs are the unknowns, the states are rolled out from
/// the current one; automatic derivatives). Input bounds are hard (Ceres bounds); rate limits are
/// penalised inside the horizon and enforced exactly on the applied command. Warm-started from the
/// previous solution shifted by one control period.
class MpcController {
 public:
  /// @throws common::InputError for an invalid config.
  explicit MpcController(const MpcConfig& config);
  ~MpcController();
  MpcController(const MpcController&) = delete;
  MpcController& operator=(const MpcController&) = delete;

  /// Solves for the command at time t [s] from `state`, tracking `reference`.
  MpcResult Solve(const MpcState& state, const common::Trajectory& reference, double t_s);

  /// Forgets the previous solution and command (the next solve starts from the reference, at rest).
  void Reset();

  const MpcConfig& config() const { return config_; }

  /// The predicted inputs of the last solve, (v, omega) per step.
  const Eigen::Matrix2Xd& predicted_inputs() const { return inputs_; }
  /// The states (x [m], y [m], yaw [rad] in W) the last solve predicts at the end of each step
  /// of its horizon under its inputs; empty before the first solve and after a failed one.
  const Eigen::Matrix3Xd& predicted_states_W() const { return predicted_states_W_; }

 private:
  struct Problem;
  // Rolls the model out from the solve's state under `inputs_` into predicted_states_W_.
  void PredictStates();
  common::Twist2 Limit(const common::Twist2& command) const;
  MpcConfig config_;
  std::unique_ptr<Problem> problem_;
  Eigen::Matrix2Xd inputs_;
  Eigen::Matrix3Xd predicted_states_W_;
  common::Twist2 last_command_{};
  bool warm_{false};
};

}  // namespace trav::controller
