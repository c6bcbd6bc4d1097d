#include "sim/actors/pose_noise.h"

#include <cmath>

#include <gtest/gtest.h>

namespace trav::sim {
namespace {

common::RobotState StateAt(double t_s) {
  common::RobotState state;
  state.time_s = t_s;
  state.X_WB.translation() = Eigen::Vector3d(1.0, 2.0, 0.3);
  return state;
}

TEST(PoseNoiseTest, WithoutNoiseItIsTheTruth) {
  PoseNoise dut{PoseNoiseConfig{}};
  const common::RobotState estimate = dut.Estimate(StateAt(0.5));
  EXPECT_TRUE(estimate.X_WB.isApprox(StateAt(0.5).X_WB, 0.0));
}

TEST(PoseNoiseTest, NoiseHasItsStandardDeviationAndRepeats) {
  PoseNoiseConfig settings;
  settings.position_noise_m = 0.1;
  settings.yaw_noise_rad = 0.05;
  PoseNoise dut(settings), again(settings);
  double sum2 = 0.0, yaw2 = 0.0;
  constexpr int kSamples = 20000;
  for (int k = 0; k < kSamples; ++k) {
    const common::RobotState truth = StateAt(0.002 * k);
    const common::RobotState estimate = dut.Estimate(truth);
    EXPECT_EQ(estimate.X_WB.translation(), again.Estimate(truth).X_WB.translation());
    sum2 += (estimate.X_WB.translation() - truth.X_WB.translation()).head<2>().squaredNorm();
    const Eigen::Vector3d forward = estimate.X_WB.linear().col(0);
    yaw2 += std::pow(std::atan2(forward.y(), forward.x()), 2);
    EXPECT_EQ(estimate.X_WB.translation().z(), truth.X_WB.translation().z());
  }
  // two axes of 0.1 m each: E|e|^2 = 0.02
  EXPECT_NEAR(sum2 / kSamples, 0.02, 0.001);
  EXPECT_NEAR(std::sqrt(yaw2 / kSamples), 0.05, 0.002);
}

TEST(PoseNoiseTest, DriftIsARandomWalkGrowingWithTheSquareRootOfTime) {
  PoseNoiseConfig settings;
  settings.drift_m_per_sqrt_s = 0.1;
  double sum2 = 0.0;
  constexpr int kWalks = 400;
  for (int w = 0; w < kWalks; ++w) {
    settings.seed = static_cast<std::uint64_t>(w + 1);
    PoseNoise dut(settings);
    for (int k = 0; k <= 100; ++k) dut.Estimate(StateAt(0.1 * k));  // 10 s
    sum2 += dut.drift_W().squaredNorm();
  }
  // two axes of 0.1 m/sqrt(s) over 10 s: E|d|^2 = 2 * 0.01 * 10 = 0.2
  EXPECT_NEAR(sum2 / kWalks, 0.2, 0.03);
}

}  // namespace
}  // namespace trav::sim
