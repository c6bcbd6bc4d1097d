#include "controller/skid_steer.h"

#include <gtest/gtest.h>

namespace trav::controller {
namespace {

using common::Wheel;

double Speed(const common::WheelSpeeds& speeds, Wheel wheel) {
  return speeds[static_cast<int>(wheel)];
}

TEST(SkidSteerTest, StraightDrivingTurnsAllWheelsAtVOverR) {
  SkidSteerConfig config;
  const common::WheelSpeeds dut = ToWheelSpeeds({1.75, 0.0}, config);
  for (double speed : dut) EXPECT_DOUBLE_EQ(speed, 1.75 / 0.0875);
}

TEST(SkidSteerTest, SpinInPlaceUsesTheEffectiveTrack) {
  SkidSteerConfig config;
  config.effective_track_factor = 2.0;
  const common::WheelSpeeds dut = ToWheelSpeeds({0.0, 1.0}, config);
  const double expected = 1.0 * 0.5 * 2.0 * 0.49 / 0.0875;
  EXPECT_DOUBLE_EQ(Speed(dut, Wheel::kFrontRight), expected);
  EXPECT_DOUBLE_EQ(Speed(dut, Wheel::kRearRight), expected);
  EXPECT_DOUBLE_EQ(Speed(dut, Wheel::kFrontLeft), -expected);
  EXPECT_DOUBLE_EQ(Speed(dut, Wheel::kRearLeft), -expected);
}

TEST(SkidSteerTest, CommandsAreClampedToTheRobotLimits) {
  SkidSteerConfig config;
  config.max_wheel_speed_rad_s = 1000.0;
  const common::Twist2 twist = FromWheelSpeeds(ToWheelSpeeds({5.0, -4.0}, config), config);
  EXPECT_NEAR(twist.v, 3.0, 1e-12);
  EXPECT_NEAR(twist.omega, -2.5, 1e-12);
}

TEST(SkidSteerTest, WheelSaturationKeepsTheCurvature) {
  SkidSteerConfig config;
  const common::Twist2 command{2.5, 2.0};
  const common::WheelSpeeds speeds = ToWheelSpeeds(command, config);
  const double largest = std::max(std::abs(Speed(speeds, Wheel::kFrontLeft)),
                                  std::abs(Speed(speeds, Wheel::kFrontRight)));
  EXPECT_DOUBLE_EQ(largest, config.max_wheel_speed_rad_s);
  const common::Twist2 achieved = FromWheelSpeeds(speeds, config);
  EXPECT_LT(achieved.v, command.v);
  EXPECT_NEAR(achieved.omega / achieved.v, command.omega / command.v, 1e-12);
}

TEST(SkidSteerTest, OdometryInvertsTheMappingWithinLimits) {
  SkidSteerConfig config;
  for (const common::Twist2 command :
       {common::Twist2{0.7, -0.3}, common::Twist2{-1.0, 0.5}, common::Twist2{0.0, 2.0}}) {
    const common::Twist2 dut = FromWheelSpeeds(ToWheelSpeeds(command, config), config);
    EXPECT_NEAR(dut.v, command.v, 1e-12);
    EXPECT_NEAR(dut.omega, command.omega, 1e-12);
  }
}

}  // namespace
}  // namespace trav::controller
