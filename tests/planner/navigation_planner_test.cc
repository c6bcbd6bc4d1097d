#include "planner/navigation_planner.h"

#include <gtest/gtest.h>

#include "common/enum_names.h"

namespace trav::planner {
namespace {

// 20 x 12 m at 0.1 m, cost 0.1, with a lethal wall at x in [4, 4.6] for y < 2.
common::GridLayers WallMap() {
  common::GridLayers map(
      common::GridGeometry::Centered(Eigen::Vector2d(4, 0), Eigen::Vector2d(20, 12), 0.1),
      {"traversability"});
  const common::GridGeometry& g = map.geometry();
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      const Eigen::Vector2d p = g.CellCenter(ix, iy);
      const bool wall = p.x() >= 4.0 && p.x() <= 4.6 && p.y() < 2.0;
      map.Layer("traversability")(ix, iy) = wall ? 1.0f : 0.1f;
    }
  }
  return map;
}

common::TrajectoryPoint Start() {
  common::TrajectoryPoint start;
  start.t_s = 1.0;
  start.position_W = Eigen::Vector2d(0.02, 0.03);
  return start;
}

TEST(NavigationPlannerTest, PlansAroundAWallToTheGoal) {
  NavigationPlanner dut(NavigationPlannerConfig{});
  const common::GridLayers map = WallMap();
  const NavigationPlan plan = dut.Plan(map, Start(), {9.0, 0.0}, {});
  ASSERT_EQ(plan.status, NavigationStatus::kPlanned) << common::NameOf(plan.optimized.status);
  EXPECT_EQ(plan.waypoints_W.front(), Start().position_W);
  EXPECT_EQ(plan.waypoints_W.back(), Eigen::Vector2d(9.0, 0.0));
  const common::Trajectory& t = plan.optimized.trajectory;
  EXPECT_EQ(t.start_time(), 1.0);
  EXPECT_LE((t.points().back().position_W - Eigen::Vector2d(9.0, 0.0)).norm(), 0.05);
  // it passes above the wall's end (its cells' edge at y = 1.95) with the clearance
  double y_at_wall = -1e9;
  for (const common::TrajectoryPoint& p : t.points()) {
    if (p.position_W.x() >= 4.0 && p.position_W.x() <= 4.6)
      y_at_wall = std::max(y_at_wall, p.position_W.y());
  }
  EXPECT_GT(y_at_wall, 1.95 + 0.95 * NavigationPlannerConfig{}.optimizer.clearance_m);
  EXPECT_GE(plan.optimized.diagnostics.min_clearance_m,
            0.95 * NavigationPlannerConfig{}.optimizer.clearance_m);
}

TEST(NavigationPlannerTest, ABlockedGoalIsMovedAndAnUnreachableOneHasNoPath) {
  common::GridLayers map = WallMap();
  const common::GridGeometry& g = map.geometry();
  // close the gap above the wall
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      const Eigen::Vector2d p = g.CellCenter(ix, iy);
      if (p.x() >= 4.0 && p.x() <= 4.6) map.Layer("traversability")(ix, iy) = 1.0f;
    }
  }
  NavigationPlanner dut(NavigationPlannerConfig{});
  // a goal inside the wall: A* moves it to the nearest reachable cell, left of the wall
  const NavigationPlan moved = dut.Plan(map, Start(), {4.3, 0.0}, {});
  EXPECT_EQ(moved.status, NavigationStatus::kPlannedToNearest);
  EXPECT_LT(moved.waypoints_W.back().x(), 4.0);
  EXPECT_GT(moved.waypoints_W.back().x(), 3.0);
  EXPECT_TRUE(moved.has_trajectory());
  // a free goal behind the closed wall: no path, no trajectory
  const NavigationPlan none = dut.Plan(map, Start(), {9.0, 0.0}, {});
  EXPECT_EQ(none.status, NavigationStatus::kNoPath);
  EXPECT_FALSE(none.has_trajectory());
  EXPECT_EQ(common::NameOf(none.status), "no-path");
}

}  // namespace
}  // namespace trav::planner
