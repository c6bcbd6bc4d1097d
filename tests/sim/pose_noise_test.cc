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

// A straight drive along x at 1 m per call.
common::RobotState AlongX(double x_m) {
  common::RobotState state;
  state.time_s = x_m;
  state.X_WB.translation() = Eigen::Vector3d(x_m, 0.0, 0.2);
  return state;
}

TEST(PoseNoiseTest, OdometryDriftGrowsWithTheDistanceNotTheTime) {
  PoseNoiseConfig settings;
  settings.method = LocalizationMethod::kDriftModel;
  PoseNoise dut(settings);
  for (int k = 0; k < 1000; ++k) {
    common::RobotState still = AlongX(0.0);
    still.time_s = 0.01 * k;
    EXPECT_TRUE(dut.Estimate(still).X_WB.isApprox(still.X_WB, 0.0));
  }
}

TEST(PoseNoiseTest, OdometryDriftHasItsRatesAfterADistance) {
  // 400 drives of 100 m: yaw error sigma_yaw * sqrt(100 m), height error sigma_z * sqrt(100 m)
  PoseNoiseConfig settings;
  settings.method = LocalizationMethod::kDriftModel;
  settings.odometry = {0.05, 0.02, 1e-3};
  double yaw2 = 0.0, z2 = 0.0;
  constexpr int kDrives = 400;
  for (int w = 0; w < kDrives; ++w) {
    settings.seed = static_cast<std::uint64_t>(w + 1);
    PoseNoise dut(settings);
    for (int k = 0; k <= 100; ++k) dut.Estimate(AlongX(k));
    yaw2 += std::pow(dut.odometry_yaw_error_rad(), 2);
    z2 += std::pow(dut.odometry_position_error_W().z(), 2);
  }
  EXPECT_NEAR(std::sqrt(yaw2 / kDrives), 1e-3 * 10.0, 0.1 * 1e-3 * 10.0);
  EXPECT_NEAR(std::sqrt(z2 / kDrives), 0.02 * 10.0, 0.1 * 0.02 * 10.0);
}

TEST(PoseNoiseTest, AHeadingErrorTurnsTheDrivenPathWithoutStretchingIt) {
  // only yaw drift: the believed path is the true one turned step by step, so every believed
  // step is as long as the true step, and the believed heading is off by the yaw error
  PoseNoiseConfig settings;
  settings.method = LocalizationMethod::kDriftModel;
  settings.odometry = {0.0, 0.0, 0.05};
  PoseNoise dut(settings);
  Eigen::Vector3d previous = dut.Estimate(AlongX(0.0)).X_WB.translation();
  for (int k = 1; k <= 50; ++k) {
    const common::RobotState estimate = dut.Estimate(AlongX(k));
    const double yaw = dut.odometry_yaw_error_rad();
    EXPECT_NEAR((estimate.X_WB.translation() - previous).norm(), 1.0, 1e-12);
    const Eigen::Vector3d forward = estimate.X_WB.linear().col(0);
    EXPECT_NEAR(std::atan2(forward.y(), forward.x()), yaw, 1e-12);
    previous = estimate.X_WB.translation();
  }
  // after 50 m of a wandering heading the believed position is off sideways
  EXPECT_GT(std::abs(dut.odometry_position_error_W().y()), 0.01);
  EXPECT_EQ(dut.odometry_position_error_W().z(), 0.0);
}

}  // namespace
}  // namespace trav::sim
