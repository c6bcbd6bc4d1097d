#include "controller/mpc_horizon.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "common/random.h"

namespace trav::controller {
namespace {

constexpr int kHorizon = 8;

// A horizon of kHorizon steps from a pose in motion, references and inputs drawn from `seed`; the
// inputs jump by up to 0.3 m/s and 0.6 rad/s from step to step, beyond the acceleration limits
// (2 m/s^2 and 6 rad/s^2 over 0.05 s steps are 0.1 m/s and 0.3 rad/s) at some steps and not at
// others.
struct Case {
  MpcConfig config;
  MpcHorizon horizon;
  std::vector<double> inputs;
};

Case MakeCase(std::uint64_t seed, double actuator_time_constant_s) {
  Case c;
  c.config.horizon = kHorizon;
  c.config.actuator_time_constant_s = actuator_time_constant_s;
  c.config.state_weights = {40.0, 30.0, 4.0};
  c.config.input_weights = {0.1, 0.2};
  c.config.rate_weights = {0.02, 0.005};
  common::Random random(seed);
  MpcHorizon& h = c.horizon;
  h.config = &c.config;
  h.x0_W = {random.Uniform(-1, 1), random.Uniform(-1, 1), random.Uniform(-3, 3)};
  h.achieved0 = {random.Uniform(0.2, 1.2), random.Uniform(-0.5, 0.5)};
  h.previous_command = {random.Uniform(0.2, 1.2), random.Uniform(-0.5, 0.5)};
  h.reference_states_W = Eigen::Matrix3Xd::Random(3, kHorizon);
  h.reference_inputs = Eigen::Matrix2Xd::Random(2, kHorizon);
  double v = h.previous_command[0], omega = h.previous_command[1];
  for (int k = 0; k < kHorizon; ++k) {
    v += random.Uniform(-0.3, 0.3);
    omega += random.Uniform(-0.6, 0.6);
    c.inputs.push_back(v);
    c.inputs.push_back(omega);
  }
  return c;
}

std::vector<double> Residuals(const MpcHorizon& h, const std::vector<double>& u) {
  std::vector<double> r(static_cast<std::size_t>(h.NumResiduals()));
  h.Evaluate(u.data(), r.data());
  return r;
}

// The closed-form Jacobian against central differences of the residuals, with and without the
// actuator's lag; the rate-limit rows are active at some steps (the test checks it is so).
TEST(MpcHorizonTest, JacobianMatchesCentralDifferences) {
  for (const double lag_s : {0.0, 0.15}) {
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
      SCOPED_TRACE(testing::Message() << "lag " << lag_s << " s, seed " << seed);
      const Case c = MakeCase(seed, lag_s);
      const MpcHorizon& h = c.horizon;
      const int rows = h.NumResiduals(), cols = h.NumInputs();
      std::vector<double> jacobian(static_cast<std::size_t>(rows * cols));
      std::vector<double> residuals(static_cast<std::size_t>(rows));
      h.Evaluate(c.inputs.data(), residuals.data(), jacobian.data());
      EXPECT_EQ(residuals, Residuals(h, c.inputs));
      int active_limits = 0;
      constexpr double kStep = 1e-6;
      for (int col = 0; col < cols; ++col) {
        std::vector<double> plus = c.inputs, minus = c.inputs;
        plus[static_cast<std::size_t>(col)] += kStep;
        minus[static_cast<std::size_t>(col)] -= kStep;
        const std::vector<double> r_plus = Residuals(h, plus), r_minus = Residuals(h, minus);
        for (int row = 0; row < rows; ++row) {
          const double numeric =
              (r_plus[static_cast<std::size_t>(row)] - r_minus[static_cast<std::size_t>(row)]) /
              (2.0 * kStep);
          const double analytic = jacobian[static_cast<std::size_t>(row * cols + col)];
          EXPECT_NEAR(analytic, numeric, 1e-6 * std::max(1.0, std::abs(numeric)))
              << "row " << row << " column " << col;
          // rows 5 and 8 of a step: the speed's and the yaw rate's rate-limit excess
          const int in_step = row % MpcHorizon::kResidualsPerStep;
          if ((in_step == 5 || in_step == 8) && analytic != 0.0) ++active_limits;
        }
      }
      EXPECT_GT(active_limits, 0);
    }
  }
}

// The state rows of the residuals are the rollout's states (States) less the reference, scaled by
// the square roots of the weights: both step the same model.
TEST(MpcHorizonTest, StateResidualsAreTheRolloutsStatesLessTheReference) {
  Case c = MakeCase(7, 0.15);
  c.config.state_weights = {1.0, 1.0, 1.0};
  const MpcHorizon& h = c.horizon;
  const Eigen::Matrix3Xd states_W = h.States(c.inputs.data());
  const std::vector<double> r = Residuals(h, c.inputs);
  for (int k = 0; k < kHorizon; ++k) {
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(r[static_cast<std::size_t>(MpcHorizon::kResidualsPerStep * k + i)],
                states_W(i, k) - h.reference_states_W(i, k));
    }
  }
  // a straight step at 1 m/s without lag moves 0.05 m along the heading
  Case straight = MakeCase(8, 0.0);
  MpcHorizon& s = straight.horizon;
  s.x0_W = {1.0, 2.0, 0.0};
  s.achieved0 = {0.0, 0.0};
  std::fill(straight.inputs.begin(), straight.inputs.end(), 0.0);
  for (int k = 0; k < kHorizon; ++k) straight.inputs[static_cast<std::size_t>(2 * k)] = 1.0;
  const Eigen::Matrix3Xd line_W = s.States(straight.inputs.data());
  for (int k = 0; k < kHorizon; ++k) {
    EXPECT_DOUBLE_EQ(line_W(0, k), 1.0 + 0.05 * (k + 1));
    EXPECT_EQ(line_W(1, k), 2.0);
    EXPECT_EQ(line_W(2, k), 0.0);
  }
}

}  // namespace
}  // namespace trav::controller
