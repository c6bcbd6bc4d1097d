#include "controller/mpc.h"

#include <algorithm>
#include <cmath>

#include <ceres/ceres.h>

#include "common/input_error.h"
#include "common/stopwatch.h"
#include "controller/mpc_horizon.h"

namespace trav::controller {

void ValidateMpcConfig(const MpcConfig& c) {
  common::RequireValue(c.horizon >= 2 && c.horizon <= 200, "horizon", c.horizon,
                       "must be in [2, 200]");
  common::RequireValue(c.step_s >= 0.005 && c.step_s <= 0.2, "step", c.step_s,
                       "must be in [0.005, 0.2]");
  common::RequireValue(c.control_period_s > 0.0 && c.control_period_s <= 0.2, "control_period",
                       c.control_period_s, "must be in (0, 0.2]");
  common::RequireValue((c.state_weights.array() >= 0.0).all(), "state_weights",
                       c.state_weights.minCoeff(), "must be >= 0");
  common::RequireValue((c.input_weights.array() >= 0.0).all(), "input_weights",
                       c.input_weights.minCoeff(), "must be >= 0");
  common::RequireValue((c.rate_weights.array() >= 0.0).all(), "rate_weights",
                       c.rate_weights.minCoeff(), "must be >= 0");
  common::RequireValue(c.max_speed_m_s > 0.0, "max_speed", c.max_speed_m_s, "must be > 0");
  common::RequireValue(c.min_speed_m_s <= 0.0, "min_speed", c.min_speed_m_s, "must be <= 0");
  common::RequireValue(c.max_yaw_rate_rad_s > 0.0, "max_yaw_rate", c.max_yaw_rate_rad_s,
                       "must be > 0");
  common::RequireValue(c.max_acceleration_m_s2 > 0.0, "max_acceleration", c.max_acceleration_m_s2,
                       "must be > 0");
  common::RequireValue(c.max_yaw_acceleration_rad_s2 > 0.0, "max_yaw_acceleration",
                       c.max_yaw_acceleration_rad_s2, "must be > 0");
  common::RequireValue(c.actuator_time_constant_s >= 0.0, "actuator_time_constant",
                       c.actuator_time_constant_s, "must be >= 0");
  common::RequireValue(c.max_iterations >= 1 && c.max_iterations <= 1000, "max_iterations",
                       c.max_iterations, "must be in [1, 1000]");
}

std::string CeresVersion() { return CERES_VERSION_STRING; }

// The horizon's data and the Ceres problem over its inputs, built once and reused by every solve
// (only the data and the initial inputs change).
struct MpcController::Problem {
  MpcHorizon horizon;
  std::vector<double> inputs;  // the decision variables (v0, w0, v1, w1, ...)
  ceres::Problem ceres_problem;
};

namespace {

// The horizon's residuals with their Jacobian in closed form (MpcHorizon::Evaluate): about a tenth
// of a solve less than Ceres's automatic differentiation over the rollout (controller_benchmark).
class HorizonCost : public ceres::CostFunction {
 public:
  explicit HorizonCost(const MpcHorizon* horizon) : horizon_(horizon) {
    set_num_residuals(horizon->NumResiduals());
    mutable_parameter_block_sizes()->push_back(horizon->NumInputs());
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    horizon_->Evaluate(parameters[0], residuals, jacobians != nullptr ? jacobians[0] : nullptr);
    return true;
  }

 private:
  const MpcHorizon* horizon_;  // owned by the controller's Problem
};

}  // namespace

MpcController::MpcController(const MpcConfig& config) : config_(config) {
  ValidateMpcConfig(config_);
  problem_ = std::make_unique<Problem>();
  Problem& p = *problem_;
  MpcHorizon& h = p.horizon;
  h.config = &config_;
  const int n = config_.horizon;
  h.reference_states_W.resize(3, n);
  h.reference_inputs.resize(2, n);
  p.inputs.assign(static_cast<std::size_t>(2 * n), 0.0);
  inputs_ = Eigen::Matrix2Xd::Zero(2, n);

  // the cost (owned by the Ceres problem) reads the horizon's data, which it does not own
  p.ceres_problem.AddResidualBlock(new HorizonCost(&h), nullptr, p.inputs.data());
  for (int k = 0; k < n; ++k) {
    p.ceres_problem.SetParameterLowerBound(p.inputs.data(), 2 * k, config_.min_speed_m_s);
    p.ceres_problem.SetParameterUpperBound(p.inputs.data(), 2 * k, config_.max_speed_m_s);
    p.ceres_problem.SetParameterLowerBound(p.inputs.data(), 2 * k + 1, -config_.max_yaw_rate_rad_s);
    p.ceres_problem.SetParameterUpperBound(p.inputs.data(), 2 * k + 1, config_.max_yaw_rate_rad_s);
  }
}

MpcController::~MpcController() = default;

void MpcController::Reset() {
  warm_ = false;
  last_command_ = common::Twist2{};
}

common::Twist2 MpcController::Limit(const common::Twist2& command) const {
  const double dv = config_.max_acceleration_m_s2 * config_.control_period_s;
  const double dw = config_.max_yaw_acceleration_rad_s2 * config_.control_period_s;
  common::Twist2 limited;
  limited.v = std::clamp(std::clamp(command.v, last_command_.v - dv, last_command_.v + dv),
                         config_.min_speed_m_s, config_.max_speed_m_s);
  limited.omega =
      std::clamp(std::clamp(command.omega, last_command_.omega - dw, last_command_.omega + dw),
                 -config_.max_yaw_rate_rad_s, config_.max_yaw_rate_rad_s);
  return limited;
}

MpcResult MpcController::Solve(const MpcState& state, const common::Trajectory& reference,
                               double t_s) {
  const common::Stopwatch start;
  Problem& p = *problem_;
  MpcHorizon& h = p.horizon;
  const int n = config_.horizon;

  // the horizon's reference, its yaw shifted by whole turns to the robot's
  const common::TrajectoryPoint now = reference.Sample(t_s);
  const double turns = std::round((state.yaw - now.yaw) / (2.0 * M_PI));
  for (int k = 0; k < n; ++k) {
    const common::TrajectoryPoint r = reference.Sample(t_s + (k + 1) * config_.step_s);
    h.reference_states_W.col(k) << r.position_W.x(), r.position_W.y(), r.yaw + 2.0 * M_PI * turns;
    h.reference_inputs.col(k) << r.v, r.omega;
  }
  h.x0_W << state.position_W.x(), state.position_W.y(), state.yaw;
  h.achieved0 << state.v, state.omega;
  h.previous_command << last_command_.v, last_command_.omega;

  // warm start: the previous inputs one control period later, else the reference inputs
  const double shift = config_.control_period_s / config_.step_s;
  for (int k = 0; k < n; ++k) {
    Eigen::Vector2d guess = h.reference_inputs.col(k);
    if (warm_) {
      const double index = std::min<double>(n - 1, k + shift);
      const int lo = static_cast<int>(index);
      const int hi = std::min(n - 1, lo + 1);
      guess = inputs_.col(lo) + (index - lo) * (inputs_.col(hi) - inputs_.col(lo));
    }
    p.inputs[2 * k] = std::clamp(guess[0], config_.min_speed_m_s, config_.max_speed_m_s);
    p.inputs[2 * k + 1] =
        std::clamp(guess[1], -config_.max_yaw_rate_rad_s, config_.max_yaw_rate_rad_s);
  }

  ceres::Solver::Options options;
  // one dense block of 2N inputs: the normal equations' Cholesky costs half of a Householder QR
  // (controller_benchmark median 1.17 -> 0.59 ms at N = 30); Levenberg-Marquardt's damping keeps
  // them well conditioned
  options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  options.max_num_iterations = config_.max_iterations;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  options.function_tolerance = 1e-8;
  options.gradient_tolerance = 1e-10;
  options.parameter_tolerance = 1e-8;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &p.ceres_problem, &summary);

  MpcResult result;
  result.iterations = static_cast<int>(summary.iterations.size());
  result.cost = summary.final_cost;
  const bool finite =
      std::all_of(p.inputs.begin(), p.inputs.end(), [](double u) { return std::isfinite(u); });
  if (summary.termination_type == ceres::FAILURE || !finite || !std::isfinite(summary.final_cost)) {
    // safe fallback: brake as hard as the limits allow, and start cold next time
    result.status = MpcStatus::kFailed;
    result.command = Limit(common::Twist2{});
    warm_ = false;
    predicted_states_W_.resize(3, 0);
  } else {
    result.status = summary.termination_type == ceres::CONVERGENCE ? MpcStatus::kSolved
                                                                   : MpcStatus::kIterationLimit;
    for (int k = 0; k < n; ++k) inputs_.col(k) << p.inputs[2 * k], p.inputs[2 * k + 1];
    result.command = Limit(common::Twist2{inputs_(0, 0), inputs_(1, 0)});
    warm_ = true;
    PredictStates();
  }
  last_command_ = result.command;
  result.solve_time_s = start.ElapsedSeconds();
  return result;
}

void MpcController::PredictStates() {
  predicted_states_W_ = problem_->horizon.States(inputs_.data());
}

}  // namespace trav::controller
