#include "controller/mpc.h"

#include <algorithm>
#include <cmath>

#include <ceres/ceres.h>
#include <ceres/dynamic_autodiff_cost_function.h>

#include "common/input_error.h"
#include "common/stopwatch.h"

namespace trav::controller {
namespace {

// Residuals per predicted step: x, y, yaw errors; input deviations; input rates; rate-limit excess.
constexpr int kResidualsPerStep = 9;
// Weight of the rate-limit excess penalty (per unit of excess acceleration).
constexpr double kRateLimitWeight = 30.0;

}  // namespace

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

namespace {

// The share of a command the achieved input takes on in one step (first-order lag; 1: none).
double LagFactor(const MpcConfig& c) {
  return c.actuator_time_constant_s > 0.0 ? std::min(1.0, c.step_s / c.actuator_time_constant_s)
                                          : 1.0;
}

// One step of the horizon's model, shared by the cost and the predicted states: the achieved
// inputs lag the command, then the unicycle moves by the midpoint rule.
template <typename T>
void StepModel(double step_s, double lag, const T command[2], T achieved[2], T* x, T* y, T* yaw) {
  using std::cos;
  using std::sin;
  for (int j = 0; j < 2; ++j) achieved[j] += lag * (command[j] - achieved[j]);
  const T mid_yaw = *yaw + 0.5 * step_s * achieved[1];
  *x += step_s * achieved[0] * cos(mid_yaw);
  *y += step_s * achieved[0] * sin(mid_yaw);
  *yaw += step_s * achieved[1];
}

}  // namespace

// The horizon's data, shared by the cost functor and the controller; the Ceres problem is built
// once and reused by every solve (only the data and the initial inputs change).
struct MpcController::Problem {
  // inputs: current state, previous command, reference states and inputs per step
  Eigen::Vector3d x0{Eigen::Vector3d::Zero()};
  Eigen::Vector2d achieved0{Eigen::Vector2d::Zero()};
  Eigen::Vector2d previous_command{Eigen::Vector2d::Zero()};
  Eigen::Matrix3Xd reference_states;
  Eigen::Matrix2Xd reference_inputs;
  std::vector<double> inputs;  // the decision variables (v0, w0, v1, w1, ...)
  ceres::Problem ceres_problem;

  const MpcConfig* config{nullptr};

  // Rolls out the unicycle (midpoint rule) and writes the residuals.
  template <typename T>
  bool operator()(T const* const* parameters, T* residuals) const {
    const MpcConfig& c = *config;
    const T* u = parameters[0];
    const Eigen::Vector3d q = c.state_weights.cwiseSqrt();
    const Eigen::Vector2d r = c.input_weights.cwiseSqrt();
    const Eigen::Vector2d rd = c.rate_weights.cwiseSqrt();
    const double limits[2] = {c.max_acceleration_m_s2, c.max_yaw_acceleration_rad_s2};
    const double lag = LagFactor(c);
    T x(x0[0]), y(x0[1]), yaw(x0[2]);
    T achieved[2] = {T(achieved0[0]), T(achieved0[1])};
    T* out = residuals;
    for (int k = 0; k < c.horizon; ++k) {
      const T command[2] = {u[2 * k], u[2 * k + 1]};
      StepModel(c.step_s, lag, command, achieved, &x, &y, &yaw);
      *out++ = q[0] * (x - reference_states(0, k));
      *out++ = q[1] * (y - reference_states(1, k));
      *out++ = q[2] * (yaw - reference_states(2, k));
      // the first rate is over one control period, from the command in force now
      const double rate_dt = k == 0 ? c.control_period_s : c.step_s;
      for (int j = 0; j < 2; ++j) {
        const T before = k == 0 ? T(previous_command[j]) : u[2 * (k - 1) + j];
        const T rate = (command[j] - before) / rate_dt;
        *out++ = r[j] * (command[j] - reference_inputs(j, k));
        *out++ = rd[j] * rate;
        // smooth excess over the rate limit: sqrt(rate^2 + eps) approximates |rate|
        const T magnitude = sqrt(rate * rate + 1e-6);
        *out++ = magnitude > limits[j] ? T(kRateLimitWeight) * (magnitude - limits[j]) : T(0.0);
      }
    }
    return true;
  }
};

MpcController::MpcController(const MpcConfig& config) : config_(config) {
  ValidateMpcConfig(config_);
  problem_ = std::make_unique<Problem>();
  Problem& p = *problem_;
  p.config = &config_;
  const int n = config_.horizon;
  p.reference_states.resize(3, n);
  p.reference_inputs.resize(2, n);
  p.inputs.assign(static_cast<std::size_t>(2 * n), 0.0);
  inputs_ = Eigen::Matrix2Xd::Zero(2, n);

  // the cost function (owned by the Ceres problem) evaluates `p` itself, which it does not own
  auto* cost = new ceres::DynamicAutoDiffCostFunction<Problem, 4>(&p, ceres::DO_NOT_TAKE_OWNERSHIP);
  cost->AddParameterBlock(2 * n);
  cost->SetNumResiduals(kResidualsPerStep * n);
  p.ceres_problem.AddResidualBlock(cost, nullptr, p.inputs.data());
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
  const int n = config_.horizon;

  // the horizon's reference, its yaw shifted by whole turns to the robot's
  const common::TrajectoryPoint now = reference.Sample(t_s);
  const double turns = std::round((state.yaw - now.yaw) / (2.0 * M_PI));
  for (int k = 0; k < n; ++k) {
    const common::TrajectoryPoint r = reference.Sample(t_s + (k + 1) * config_.step_s);
    p.reference_states.col(k) << r.position_W.x(), r.position_W.y(), r.yaw + 2.0 * M_PI * turns;
    p.reference_inputs.col(k) << r.v, r.omega;
  }
  p.x0 << state.position_W.x(), state.position_W.y(), state.yaw;
  p.achieved0 << state.v, state.omega;
  p.previous_command << last_command_.v, last_command_.omega;

  // warm start: the previous inputs one control period later, else the reference inputs
  const double shift = config_.control_period_s / config_.step_s;
  for (int k = 0; k < n; ++k) {
    Eigen::Vector2d guess = p.reference_inputs.col(k);
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
  const Problem& p = *problem_;
  const double lag = LagFactor(config_);
  double x = p.x0[0], y = p.x0[1], yaw = p.x0[2];
  double achieved[2] = {p.achieved0[0], p.achieved0[1]};
  predicted_states_W_.resize(3, config_.horizon);
  for (int k = 0; k < config_.horizon; ++k) {
    const double command[2] = {inputs_(0, k), inputs_(1, k)};
    StepModel(config_.step_s, lag, command, achieved, &x, &y, &yaw);
    predicted_states_W_.col(k) << x, y, yaw;
  }
}

}  // namespace trav::controller
