#include "controller/mpc_horizon.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace trav::controller {
namespace {

// The share of a command the achieved input takes on in one step (first-order lag; 1: none).
double LagFactor(const MpcConfig& c) {
  return c.actuator_time_constant_s > 0.0 ? std::min(1.0, c.step_s / c.actuator_time_constant_s)
                                          : 1.0;
}

// The rollout's state as it steps: the achieved inputs and the pose in W.
struct RolloutState {
  double achieved[2];
  double x, y, yaw;
  double mid_yaw{0.0};  // the yaw at the middle of the last step
};

// One step of the model: the achieved inputs lag the command, then the unicycle moves by the
// midpoint rule.
void Step(double step_s, double lag, const double command[2], RolloutState* s) {
  for (int j = 0; j < 2; ++j) s->achieved[j] += lag * (command[j] - s->achieved[j]);
  s->mid_yaw = s->yaw + 0.5 * step_s * s->achieved[1];
  s->x += step_s * s->achieved[0] * std::cos(s->mid_yaw);
  s->y += step_s * s->achieved[0] * std::sin(s->mid_yaw);
  s->yaw += step_s * s->achieved[1];
}

RolloutState Start(const MpcHorizon& h) {
  return {{h.achieved0[0], h.achieved0[1]}, h.x0_W[0], h.x0_W[1], h.x0_W[2]};
}

// The rate of input j at step k under `u`, and the time it is taken over [s].
double RateDt(const MpcConfig& c, int k) { return k == 0 ? c.control_period_s : c.step_s; }
double Rate(const MpcHorizon& h, const double* u, int k, int j) {
  const double before = k == 0 ? h.previous_command[j] : u[2 * (k - 1) + j];
  return (u[2 * k + j] - before) / RateDt(*h.config, k);
}

// The smooth |rate| of the rate-limit residual: sqrt(rate^2 + eps) approximates |rate|.
double SmoothMagnitude(double rate) { return std::sqrt(rate * rate + 1e-6); }

double AccelerationLimit(const MpcConfig& c, int j) {
  return j == 0 ? c.max_acceleration_m_s2 : c.max_yaw_acceleration_rad_s2;
}

}  // namespace

Eigen::Matrix3Xd MpcHorizon::States(const double* u) const {
  const MpcConfig& c = *config;
  const double lag = LagFactor(c);
  RolloutState s = Start(*this);
  Eigen::Matrix3Xd states_W(3, c.horizon);
  for (int k = 0; k < c.horizon; ++k) {
    Step(c.step_s, lag, u + 2 * k, &s);
    states_W.col(k) << s.x, s.y, s.yaw;
  }
  return states_W;
}

void MpcHorizon::Evaluate(const double* u, double* residuals, double* jacobian) const {
  const MpcConfig& c = *config;
  const Eigen::Vector3d q = c.state_weights.cwiseSqrt();
  const Eigen::Vector2d r = c.input_weights.cwiseSqrt();
  const Eigen::Vector2d rd = c.rate_weights.cwiseSqrt();
  const double lag = LagFactor(c);
  // the rollout's achieved speeds and midpoint yaws, on which every sensitivity depends
  speed_.resize(static_cast<std::size_t>(c.horizon));
  mid_yaw_.resize(static_cast<std::size_t>(c.horizon));
  RolloutState s = Start(*this);
  double* out = residuals;
  for (int k = 0; k < c.horizon; ++k) {
    Step(c.step_s, lag, u + 2 * k, &s);
    speed_[static_cast<std::size_t>(k)] = s.achieved[0];
    mid_yaw_[static_cast<std::size_t>(k)] = s.mid_yaw;
    *out++ = q[0] * (s.x - reference_states_W(0, k));
    *out++ = q[1] * (s.y - reference_states_W(1, k));
    *out++ = q[2] * (s.yaw - reference_states_W(2, k));
    for (int j = 0; j < 2; ++j) {
      const double rate = Rate(*this, u, k, j);
      *out++ = r[j] * (u[2 * k + j] - reference_inputs(j, k));
      *out++ = rd[j] * rate;
      const double magnitude = SmoothMagnitude(rate);
      const double limit = AccelerationLimit(c, j);
      *out++ = magnitude > limit ? kRateLimitWeight * (magnitude - limit) : 0.0;
    }
  }
  if (jacobian != nullptr) JacobianOfRollout(u, jacobian);
}

void MpcHorizon::JacobianOfRollout(const double* u, double* jacobian) const {
  const MpcConfig& c = *config;
  const int n = c.horizon;
  const int cols = NumInputs();
  std::fill(jacobian, jacobian + static_cast<std::ptrdiff_t>(NumResiduals()) * cols, 0.0);
  auto at = [&](int row, int col) -> double& {
    return jacobian[static_cast<std::ptrdiff_t>(row) * cols + col];
  };
  const Eigen::Vector3d q = c.state_weights.cwiseSqrt();
  const Eigen::Vector2d r = c.input_weights.cwiseSqrt();
  const Eigen::Vector2d rd = c.rate_weights.cwiseSqrt();
  const double lag = LagFactor(c);
  const double h = c.step_s;
  const std::vector<double>& speed = speed_;
  const std::vector<double>& mid_yaw = mid_yaw_;
  for (int j = 0; j < n; ++j) {
    // the speed command of step j moves the achieved speed of steps k >= j by lag (1 - lag)^(k-j)
    double d_speed = lag, dx = 0.0, dy = 0.0;
    for (int k = j; k < n; ++k) {
      const auto kk = static_cast<std::size_t>(k);
      dx += h * std::cos(mid_yaw[kk]) * d_speed;
      dy += h * std::sin(mid_yaw[kk]) * d_speed;
      at(kResidualsPerStep * k, 2 * j) = q[0] * dx;
      at(kResidualsPerStep * k + 1, 2 * j) = q[1] * dy;
      d_speed *= 1.0 - lag;
    }
    // the yaw-rate command of step j moves the achieved yaw rate, hence the yaw and the midpoint
    // yaw of steps k >= j
    double d_rate = lag, d_yaw = 0.0;
    dx = dy = 0.0;
    for (int k = j; k < n; ++k) {
      const auto kk = static_cast<std::size_t>(k);
      const double d_mid = d_yaw + 0.5 * h * d_rate;
      dx -= h * speed[kk] * std::sin(mid_yaw[kk]) * d_mid;
      dy += h * speed[kk] * std::cos(mid_yaw[kk]) * d_mid;
      d_yaw += h * d_rate;
      at(kResidualsPerStep * k, 2 * j + 1) = q[0] * dx;
      at(kResidualsPerStep * k + 1, 2 * j + 1) = q[1] * dy;
      at(kResidualsPerStep * k + 2, 2 * j + 1) = q[2] * d_yaw;
      d_rate *= 1.0 - lag;
    }
  }
  // each input's deviation, rate and rate-limit excess depend on it and on the step before
  for (int k = 0; k < n; ++k) {
    const double dt = RateDt(c, k);
    for (int j = 0; j < 2; ++j) {
      const int row = kResidualsPerStep * k + 3 + 3 * j;
      at(row, 2 * k + j) = r[j];
      at(row + 1, 2 * k + j) = rd[j] / dt;
      if (k > 0) at(row + 1, 2 * (k - 1) + j) = -rd[j] / dt;
      const double rate = Rate(*this, u, k, j);
      const double magnitude = SmoothMagnitude(rate);
      if (magnitude > AccelerationLimit(c, j)) {
        const double d = kRateLimitWeight * rate / magnitude / dt;
        at(row + 2, 2 * k + j) = d;
        if (k > 0) at(row + 2, 2 * (k - 1) + j) = -d;
      }
    }
  }
}

}  // namespace trav::controller
