#include "planner/pose_search.h"

#include <cmath>

#include "planner_test_util.h"
#include <gtest/gtest.h>

#include "common/footprint.h"
#include "planner/manoeuvres.h"

namespace trav::planner {
namespace {

// 16 x 12 m at 0.1 m, free (cost 0.1), centred on the origin.
common::GridLayers OpenMap() {
  common::GridLayers map(
      common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(16, 12), 0.1),
      {"traversability"});
  map.Layer("traversability").setConstant(0.1f);
  return map;
}

common::Pose2 PoseAt(double x, double y, double yaw) {
  common::Pose2 pose;
  pose.position = Eigen::Vector2d(x, y);
  pose.yaw = yaw;
  return pose;
}

// The Scout Mini's footprint searched with 0.1 m of clearance on `map`.
struct Searcher {
  explicit Searcher(const common::GridLayers& map) : field(map, CostMapConfig{}) {}

  std::optional<std::vector<common::Pose2>> operator()(const common::Pose2& start,
                                                       const Eigen::Vector2d& goal_W) const {
    return SearchPoses(field, body_B, footprint.CircumscribedRadius(), kClearance_m, start, goal_W,
                       config);
  }

  // The way at creep speed, as the planner takes it.
  common::Trajectory Creep(const common::Pose2& start,
                           const std::vector<common::Pose2>& poses) const {
    common::TrajectoryPoint from;
    from.position_W = start.position;
    from.yaw = start.yaw;
    return CreepThrough(from, poses, FallbackConfig{});
  }

  static constexpr double kClearance_m = 0.1;
  CostField field;
  common::Footprint footprint;
  std::vector<Eigen::Vector2d> body_B{footprint.BoundaryPoints_B(0.1)};
  FallbackConfig config;
};

TEST(PoseSearchTest, DrivesStraightToAGoalAhead) {
  const Searcher search(OpenMap());
  const auto poses = search(PoseAt(0, 0, 0), {2, 0});
  ASSERT_TRUE(poses.has_value());
  // one drive, ending on the first lattice point within a cell of the goal
  ASSERT_EQ(poses->size(), 1u);
  EXPECT_NEAR((poses->front().position - Eigen::Vector2d(1.9, 0)).norm(), 0.0, 1e-12);
  EXPECT_EQ(poses->front().yaw, 0.0);
}

TEST(PoseSearchTest, TurnsInPlaceOnceThenDrives) {
  const Searcher search(OpenMap());
  // facing +y with the goal along +x: a quarter turn, then 1.9 m
  const auto poses = search(PoseAt(0, 0, 0.5 * M_PI), {2, 0});
  ASSERT_TRUE(poses.has_value());
  ASSERT_EQ(poses->size(), 1u);
  EXPECT_NEAR((poses->front().position - Eigen::Vector2d(1.9, 0)).norm(), 0.0, 1e-12);
  EXPECT_EQ(poses->front().yaw, 0.0);
  const common::Trajectory way = search.Creep(PoseAt(0, 0, 0.5 * M_PI), *poses);
  EXPECT_NEAR(way.end_time(), 0.5 * M_PI / 0.6 + 1.9 / 0.3, 1e-9);
  // a start within a cell of the goal needs no way
  EXPECT_TRUE(search(PoseAt(0, 0, 1.0), {0.05, 0.05})->empty());
}

// A dead end 0.8 m wide along x, closed at x = 1 and open at x = -3: too narrow to turn the
// 0.85 m circumscribed disc in.
common::GridLayers DeadEndMap() {
  common::GridLayers map = OpenMap();
  test_util::Paint(&map, 1.0f, [](const Eigen::Vector2d& p) {
    return p.x() > -3.0 && p.x() < 1.2 && (std::abs(p.y()) > 0.4 || p.x() > 1.0) &&
           std::abs(p.y()) < 0.7;
  });
  return map;
}

TEST(PoseSearchTest, BacksOutOfADeadEndThenTurnsRound) {
  Searcher search(DeadEndMap());
  search.config.search_reach_m = 8.0;
  const common::Pose2 start = PoseAt(0.55, 0, 0);  // the front 0.137 m from the end
  const auto poses = search(start, {-6, 0});
  ASSERT_TRUE(poses.has_value());
  // backward out of the dead end facing its end, a half turn outside (two poses: a merged turn
  // stays within 3 pi / 4, so that it goes the shorter way), forward to the goal
  ASSERT_EQ(poses->size(), 3u);
  EXPECT_EQ((*poses)[0].yaw, 0.0);
  EXPECT_NEAR((*poses)[0].position.y(), 0.0, 1e-12);
  EXPECT_LT((*poses)[0].position.x(), -3.0);  // the base out of the dead end's mouth
  EXPECT_EQ((*poses)[1].position, (*poses)[0].position);
  EXPECT_NEAR(std::abs((*poses)[1].yaw), 0.75 * M_PI, 1e-12);
  EXPECT_NEAR(std::abs((*poses)[2].yaw), M_PI, 1e-12);
  EXPECT_LE(((*poses)[2].position - Eigen::Vector2d(-6, 0)).norm(), 0.1);
  const common::Trajectory way = search.Creep(start, *poses);
  EXPECT_LT(way.Sample(1.0).v, 0.0);
  EXPECT_GT(way.Sample(way.end_time() - 1.0).v, 0.0);
  EXPECT_TRUE(KeepsClear(search.field, way, search.body_B, Searcher::kClearance_m));
}

TEST(PoseSearchTest, TurnsInTheRoomBehindADoorwayThatOpensOntoAWall) {
  // a wall at x = 0 with a 1.0 m door; 1.4 m into the room a wall across the door, 3 m wide;
  // the goal round its end. The robot stands in the doorway facing the wall.
  common::GridLayers map = OpenMap();
  test_util::Paint(&map, 1.0f, [](const Eigen::Vector2d& p) {
    const bool door_wall = std::abs(p.x()) < 0.1 && std::abs(p.y()) > 0.5;
    const bool across = std::abs(p.x() - 1.5) < 0.1 && std::abs(p.y()) < 1.5;
    return door_wall || across;
  });
  const Searcher search(map);
  const common::Pose2 start = PoseAt(0.1, 0, 0);
  const auto poses = search(start, {2.5, 2.5});
  ASSERT_TRUE(poses.has_value());
  // it turns in the room: short of the wall's end (y < 1.5) every pose lies between the two walls,
  // and one of them heads along the walls (within 30 deg of +y)
  bool turned = false;
  for (const common::Pose2& pose : *poses) {
    if (pose.position.y() >= 1.5) continue;
    EXPECT_GT(pose.position.x(), 0.1);
    EXPECT_LT(pose.position.x(), 1.4);
    turned = turned || std::abs(pose.yaw - 0.5 * M_PI) < M_PI / 6.0;
  }
  EXPECT_TRUE(turned);
  EXPECT_LE((poses->back().position - Eigen::Vector2d(2.5, 2.5)).norm(), 0.1);
  const common::Trajectory way = search.Creep(start, *poses);
  EXPECT_TRUE(KeepsClear(search.field, way, search.body_B, Searcher::kClearance_m));
  // deterministic
  const auto again = search(start, {2.5, 2.5});
  ASSERT_EQ(again->size(), poses->size());
  for (std::size_t i = 0; i < poses->size(); ++i) {
    EXPECT_EQ((*again)[i].position, (*poses)[i].position);
    EXPECT_EQ((*again)[i].yaw, (*poses)[i].yaw);
  }
}

TEST(PoseSearchTest, FindsNoWayOutOfAClosedRoomOrBeyondItsExpansions) {
  common::GridLayers map = OpenMap();
  test_util::Paint(&map, 1.0f, [](const Eigen::Vector2d& p) {
    return std::abs(p.norm() - 1.5) < 0.1;  // a ring round the start
  });
  const Searcher closed(map);
  EXPECT_FALSE(closed(PoseAt(0, 0, 0), {3, 0}).has_value());
  Searcher hasty(OpenMap());
  hasty.config.search_expansions = 10;
  EXPECT_FALSE(hasty(PoseAt(0, 0, 0), {3, 0}).has_value());
  hasty.config.search_expansions = 200;
  EXPECT_TRUE(hasty(PoseAt(0, 0, 0), {3, 0}).has_value());
}

}  // namespace
}  // namespace trav::planner
