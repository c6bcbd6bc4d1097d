#include "planner/manoeuvres.h"

#include <cmath>
#include <optional>
#include <vector>

#include "planner_test_util.h"
#include <gtest/gtest.h>

#include "common/footprint.h"

namespace trav::planner {
namespace {

common::TrajectoryPoint StartAt(double x, double y, double yaw) {
  common::TrajectoryPoint start;
  start.t_s = 2.0;
  start.position_W = Eigen::Vector2d(x, y);
  start.yaw = yaw;
  start.v = 0.7;  // a creep starts from rest whatever the robot did
  return start;
}

TEST(ManoeuvresTest, StopFromBrakesAlongTheHeadingAtTheBrakingDeceleration) {
  FallbackConfig config;
  config.braking_m_s2 = 1.5;
  common::TrajectoryPoint start = StartAt(1, 2, 0.5 * M_PI);
  start.v = 0.6;  // 0.4 s and 0.12 m to rest, sampled every 0.02 s
  const std::vector<common::TrajectoryPoint> stop = StopFrom(start, config).points();
  ASSERT_EQ(stop.size(), 21U);
  EXPECT_EQ(stop.front().v, 0.6);
  EXPECT_NEAR(stop[10].v, 0.3, 1e-12);
  EXPECT_EQ(stop[10].acceleration, -1.5);
  EXPECT_NEAR(stop.back().t_s, 2.4, 1e-12);
  EXPECT_NEAR((stop.back().position_W - Eigen::Vector2d(1, 2.12)).norm(), 0.0, 1e-12);
  EXPECT_EQ(stop.back().v, 0.0);
  EXPECT_EQ(stop.back().acceleration, 0.0);
  // backward and turning: the yaw rate falls to zero with the speed (half its turn over 0.4 s)
  start.v = -0.6;
  start.omega = 0.5;
  const common::TrajectoryPoint rest = StopFrom(start, config).points().back();
  EXPECT_NEAR(rest.yaw, 0.5 * M_PI + 0.1, 1e-12);
  EXPECT_EQ(rest.omega, 0.0);
  EXPECT_NEAR(rest.position_W.y(), 2.0 - 0.12, 1e-3);
  EXPECT_GT(rest.position_W.x(), 1.0);  // backward, the heading turned past +y
  // at rest: the start alone
  start.v = 0.0;
  EXPECT_EQ(StopFrom(start, config).points().size(), 1U);
}

// A robot turning at 2 rad/s (0.6 m radius) onto a straight: stopped along the path it follows, it
// straightens with it where the heading's arc would keep turning.
TEST(ManoeuvresTest, StopAlongBrakesOnThePathsOwnPositionsAndYaws) {
  const common::Trajectory path = test_util::TurnThenStraight(2.0, 1.2, 0.05, 2.0, 2.0);
  FallbackConfig config;  // 2 m/s^2: 0.6 s and 0.36 m to rest, sampled every 0.02 s
  const common::TrajectoryPoint start = path.Sample(2.0);
  const std::optional<common::Trajectory> stop = StopAlong(path, start, config);
  ASSERT_TRUE(stop.has_value());
  const std::vector<common::TrajectoryPoint>& points = stop->points();
  ASSERT_EQ(points.size(), 31U);
  EXPECT_EQ(points.front().position_W, start.position_W);
  // the turn's 0.05 m (1/12 rad), then 0.31 m straight on
  const double turned = 0.05 / 0.6;
  const Eigen::Vector2d turn_end(0.6 * std::sin(turned), 0.6 * (1.0 - std::cos(turned)));
  const Eigen::Vector2d rest_W =
      turn_end + 0.31 * Eigen::Vector2d(std::cos(turned), std::sin(turned));
  EXPECT_LT((points.back().position_W - rest_W).norm(), 1e-3);
  EXPECT_NEAR(points.back().yaw, turned, 1e-3);
  EXPECT_NEAR(points.back().t_s, 2.6, 1e-12);
  EXPECT_EQ(points.back().v, 0.0);
  EXPECT_EQ(points.back().omega, 0.0);
  // half way in time: half the speed, 0.27 m along; in the turn the yaw rate scales with the speed
  EXPECT_NEAR(points[15].v, 0.6, 1e-12);
  EXPECT_NEAR(points[15].position_W.x(), turn_end.x() + 0.22 * std::cos(turned), 1e-3);
  EXPECT_NEAR(points[1].omega, 2.0 * 1.16 / 1.2, 1e-9);
  EXPECT_EQ(points[15].omega, 0.0);
  // the heading's arc keeps the turn's curvature: a quarter of a radian more
  EXPECT_NEAR(StopFrom(start, config).points().back().yaw, 0.6, 1e-12);
  // nothing when the path ends before the stop would (0.24 m), or at rest
  const common::Trajectory short_path = test_util::TurnThenStraight(2.0, 1.2, 0.0, 0.0, 0.2);
  EXPECT_FALSE(StopAlong(short_path, short_path.Sample(2.0), config).has_value());
  common::TrajectoryPoint rest = start;
  rest.v = 0.0;
  EXPECT_FALSE(StopAlong(path, rest, config).has_value());
}

TEST(ManoeuvresTest, CreepAlongTurnsInPlaceAtEachVertexThenDrivesStraight) {
  FallbackConfig config;  // 0.3 m/s, 0.6 rad/s
  const common::Trajectory t =
      CreepAlong(StartAt(0, 0, 0), {{0, 0}, {1.5, 0}, {1.5, 0.9}}, false, config);
  // 1.5 m at 0.3 m/s, a quarter turn at 0.6 rad/s, 0.9 m at 0.3 m/s
  const double turn_s = 0.5 * M_PI / 0.6;
  EXPECT_NEAR(t.end_time() - t.start_time(), 5.0 + turn_s + 3.0, 1e-9);
  EXPECT_EQ(t.points().front().v, 0.0);
  const common::TrajectoryPoint straight = t.Sample(2.0 + 2.5);
  EXPECT_NEAR(straight.position_W.x(), 0.75, 1e-9);
  EXPECT_EQ(straight.v, 0.3);
  const common::TrajectoryPoint turning = t.Sample(2.0 + 5.0 + 0.5 * turn_s);
  EXPECT_NEAR((turning.position_W - Eigen::Vector2d(1.5, 0)).norm(), 0.0, 1e-9);
  EXPECT_NEAR(turning.yaw, 0.25 * M_PI, 1e-9);
  EXPECT_EQ(turning.omega, 0.6);
  const common::TrajectoryPoint end = t.points().back();
  EXPECT_NEAR((end.position_W - Eigen::Vector2d(1.5, 0.9)).norm(), 0.0, 1e-9);
  EXPECT_NEAR(end.yaw, 0.5 * M_PI, 1e-9);
  EXPECT_EQ(end.v, 0.0);
}

TEST(ManoeuvresTest, ReverseDrivesBackwardFacingAwayFromTheSegment) {
  const common::Trajectory t = CreepAlong(
      StartAt(1, 1, 0.3), {{1, 1}, {1 - std::cos(0.3), 1 - std::sin(0.3)}}, true, FallbackConfig{});
  // already facing away: no turn, 1 m backward at 0.3 m/s
  EXPECT_NEAR(t.end_time() - t.start_time(), 1.0 / 0.3, 1e-9);
  EXPECT_EQ(t.Sample(3.0).v, -0.3);
  EXPECT_NEAR(t.Sample(3.0).yaw, 0.3, 1e-12);
}

TEST(ManoeuvresTest, CreepThroughTurnsToEachPoseThenDrivesForwardOrBackward) {
  common::Pose2 ahead, behind;
  ahead.position = Eigen::Vector2d(1, 0);
  behind.position = Eigen::Vector2d(1, -0.5);
  behind.yaw = 0.5 * M_PI;  // facing +y, so backward to y = -0.5
  const common::Trajectory t = CreepThrough(StartAt(0, 0, 0), {ahead, behind}, FallbackConfig{});
  const double turn_s = 0.5 * M_PI / 0.6;
  EXPECT_NEAR(t.end_time() - t.start_time(), 1.0 / 0.3 + turn_s + 0.5 / 0.3, 1e-9);
  EXPECT_EQ(t.Sample(2.0 + 1.5).v, 0.3);
  EXPECT_EQ(t.Sample(2.0 + 1.0 / 0.3 + 0.5 * turn_s).omega, 0.6);
  const common::TrajectoryPoint reversing = t.Sample(t.end_time() - 0.5);
  EXPECT_EQ(reversing.v, -0.3);
  EXPECT_NEAR(reversing.yaw, 0.5 * M_PI, 1e-12);
  EXPECT_NEAR((t.points().back().position_W - behind.position).norm(), 0.0, 1e-9);
}

TEST(ManoeuvresTest, TurnInPlaceTakesTheShorterWayRound) {
  const common::Trajectory t = TurnInPlace(StartAt(0, 0, 3.0), -3.0, FallbackConfig{});
  const double turn = 2.0 * M_PI - 6.0;  // +0.283 rad through pi
  EXPECT_NEAR(t.end_time() - t.start_time(), turn / 0.6, 1e-9);
  EXPECT_NEAR(t.points().back().yaw, 3.0 + turn, 1e-9);
  EXPECT_EQ(t.points().back().position_W, Eigen::Vector2d(0, 0));
}

TEST(ManoeuvresTest, KeepsClearRejectsGettingCloserButNotStartingClose) {
  // a wall whose cells (0.1 m) begin at x = 2
  common::GridLayers map(
      common::GridGeometry::Centered(Eigen::Vector2d(5, 0), Eigen::Vector2d(16, 10), 0.1),
      {"traversability"});
  map.Layer("traversability").setConstant(0.1f);
  test_util::Paint(&map, 1.0f, [](const Eigen::Vector2d& p) { return p.x() >= 2.0; });
  const CostField field(map, CostMapConfig{});
  const std::vector<Eigen::Vector2d> body = common::Footprint{}.BoundaryPoints_B(0.1);
  // the front is 0.313 m ahead of the base: at x = 1.5 it is 0.187 m from the wall
  const common::Trajectory away = CreepAlong(StartAt(1.5, 0, 0), {{1.5, 0}, {1.0, 0}}, true, {});
  EXPECT_TRUE(KeepsClear(field, away, body, 0.3));  // starts closer than 0.3 m, never gets closer
  const common::Trajectory toward = CreepAlong(StartAt(1.5, 0, 0), {{1.5, 0}, {1.6, 0}}, false, {});
  EXPECT_FALSE(KeepsClear(field, toward, body, 0.3));
  EXPECT_TRUE(KeepsClear(field, CreepAlong(StartAt(0, 0, 0), {{0, 0}, {1.0, 0}}, false, {}), body,
                         0.3));  // ends 0.687 m from it
}

}  // namespace
}  // namespace trav::planner
