#include "common/trajectory.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

namespace trav::common {
namespace {

TEST(TrajectoryTest, AnEmptyTrajectoryRefusesToBeSampled) {
  const Trajectory empty;
  EXPECT_THROW(empty.Sample(0.0), PreconditionError);
  EXPECT_THROW(empty.start_time(), PreconditionError);
  EXPECT_THROW(empty.end_time(), PreconditionError);
  try {
    empty.Sample(1.0);
  } catch (const PreconditionError& e) {
    EXPECT_NE(std::string(e.what()).find("!points_.empty() does not hold"), std::string::npos)
        << e.what();
  }
}

TEST(TrajectoryTest, SamplesInterpolateAndHoldTheEnds) {
  const Trajectory dut({{0.0, {0, 0}, 0.0, 1.0, 0.0, 0.0}, {1.0, {1, 2}, 1.0, 2.0, 0.5, 1.0}});
  const TrajectoryPoint mid = dut.Sample(0.25);
  EXPECT_DOUBLE_EQ(mid.position_W.x(), 0.25);
  EXPECT_DOUBLE_EQ(mid.position_W.y(), 0.5);
  EXPECT_DOUBLE_EQ(mid.yaw, 0.25);
  EXPECT_DOUBLE_EQ(mid.v, 1.25);
  EXPECT_DOUBLE_EQ(dut.Sample(-1.0).position_W.x(), 0.0);
  EXPECT_DOUBLE_EQ(dut.Sample(5.0).position_W.y(), 2.0);
  EXPECT_THROW(Trajectory({{1.0, {0, 0}}, {1.0, {1, 0}}}), std::invalid_argument);
}

TEST(TrajectoryTest, AlongACircleTheSpeedYawAndYawRateMatchTheGeometry) {
  std::vector<Eigen::Vector2d> circle;
  for (double a = 0.0; a <= 2.0 * M_PI; a += 0.005)
    circle.emplace_back(2.0 * std::sin(a), 2.0 * (1.0 - std::cos(a)));
  const Trajectory dut = TrajectoryAlongPath(circle, 1.0, 0.5);
  // ramps of 2 s at 0.5 m/s^2 (1 m each) around a 12.57 m cruise
  EXPECT_NEAR(dut.end_time(), 2.0 + 2.0 + (2.0 * M_PI * 2.0 - 2.0) / 1.0, 0.02);
  const TrajectoryPoint cruise = dut.Sample(6.0);
  EXPECT_NEAR(cruise.v, 1.0, 1e-9);
  EXPECT_NEAR(cruise.omega, 0.5, 0.01);  // v / radius
  EXPECT_NEAR(cruise.position_W.norm(), cruise.position_W.norm(), 0.0);
  EXPECT_NEAR((cruise.position_W - Eigen::Vector2d(0, 2)).norm(), 2.0, 1e-3);
  // heading is the tangent of the circle
  const Eigen::Vector2d radial = cruise.position_W - Eigen::Vector2d(0, 2);
  EXPECT_NEAR(std::cos(cruise.yaw) * radial.x() + std::sin(cruise.yaw) * radial.y(), 0.0, 0.01);
  // starts and ends at rest
  EXPECT_EQ(dut.Sample(0.0).v, 0.0);
  EXPECT_NEAR(dut.Sample(dut.end_time()).v, 0.0, 1e-9);
  // yaw is continuous over the full turn
  EXPECT_NEAR(dut.Sample(dut.end_time()).yaw - dut.Sample(0.0).yaw, 2.0 * M_PI, 0.05);
}

}  // namespace
}  // namespace trav::common
