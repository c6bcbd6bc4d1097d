#include "planner/astar.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include <gtest/gtest.h>

#include "common/random.h"
#include "planner/obstacle_memory.h"
#include "tests/planner/planner_test_util.h"

namespace trav::planner {
namespace {

using test_util::Paint;

// A 10 x 10 m map at 0.1 m, every cell easy (cost 0).
common::GridLayers EmptyMap() {
  common::GridLayers map(
      common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(10, 10), 0.1),
      {"traversability"});
  map.Layer("traversability").setZero();
  return map;
}

double Length(const std::vector<Eigen::Vector2d>& points) {
  double length = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i) length += (points[i] - points[i - 1]).norm();
  return length;
}

TEST(AStarTest, OnAnEmptyGridThePathIsTheStraightLine) {
  const GridPath dut = GridPlanner(EmptyMap(), AStarConfig{}).Plan({-4, 0}, {4, 0});
  ASSERT_EQ(dut.status, PlanStatus::kFound);
  EXPECT_NEAR(dut.cost, 8.0, 1e-9);
  EXPECT_EQ(dut.points_W.size(), 81u);
  for (const Eigen::Vector2d& p : dut.points_W) EXPECT_NEAR(p.y(), 0.0, 1e-9);
  // diagonal: octile moves only
  const GridPath diagonal = GridPlanner(EmptyMap(), AStarConfig{}).Plan({-4, -4}, {4, 4});
  EXPECT_NEAR(diagonal.cost, 8.0 * std::sqrt(2.0), 1e-9);
}

// Dijkstra over the same edge costs, written independently of the planner, for the optimal cost.
double DijkstraCost(const common::GridLayers& map, const Eigen::Vector2i& start,
                    const Eigen::Vector2i& goal, double w) {
  const common::GridGeometry& g = map.geometry();
  const Eigen::MatrixXf& c = map.Layer("traversability");
  Eigen::MatrixXd best = Eigen::MatrixXd::Constant(g.num_x, g.num_y, 1e18);
  Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> done =
      Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>::Constant(g.num_x, g.num_y, false);
  best(start.x(), start.y()) = 0.0;
  for (int round = 0; round < g.num_x * g.num_y; ++round) {
    int bx = -1, by = -1;
    for (int ix = 0; ix < g.num_x; ++ix) {
      for (int iy = 0; iy < g.num_y; ++iy) {
        if (!done(ix, iy) && (bx < 0 || best(ix, iy) < best(bx, by))) bx = ix, by = iy;
      }
    }
    done(bx, by) = true;
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        const int jx = bx + dx, jy = by + dy;
        if ((dx == 0 && dy == 0) || !g.Contains(jx, jy)) continue;
        const double length = g.resolution_m * std::hypot(dx, dy);
        best(jx, jy) = std::min(
            best(jx, jy),
            best(bx, by) + length * (1.0 + w * 0.5 * (double{c(bx, by)} + double{c(jx, jy)})));
      }
    }
  }
  return best(goal.x(), goal.y());
}

TEST(AStarTest, FindsTheOptimalCostOnRandomMaps) {
  common::Random random(9);
  for (int trial = 0; trial < 3; ++trial) {
    common::GridLayers map(
        common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(3, 3), 0.1),
        {"traversability"});
    Eigen::MatrixXf& c = map.Layer("traversability");
    for (Eigen::Index i = 0; i < c.size(); ++i)
      c.data()[i] = static_cast<float>(0.2 + 0.5 * random.Uniform());
    AStarConfig config;
    config.lethal_threshold = 2.0;  // nothing blocked
    const GridPath dut = GridPlanner(map, config).Plan({-1.5, -1.5}, {1.4, 1.2});
    ASSERT_EQ(dut.status, PlanStatus::kFound);
    EXPECT_NEAR(
        dut.cost,
        DijkstraCost(map, {0, 0}, *map.geometry().CellIndex({1.4, 1.2}), config.cost_weight), 1e-9);
  }
}

TEST(AStarTest, GoesThroughTheGapOfAWall) {
  common::GridLayers map = EmptyMap();
  // a wall at x = 0 with a 1 m gap at y in [2, 3]
  Paint(&map, 1.0f, [](const Eigen::Vector2d& p) {
    return std::abs(p.x()) < 0.15 && !(p.y() > 2.0 && p.y() < 3.0);
  });
  AStarConfig config;
  config.inflation_radius_m = 0.2;
  const GridPath dut = GridPlanner(map, config).Plan({-3, 0}, {3, 0});
  ASSERT_EQ(dut.status, PlanStatus::kFound);
  bool through_gap = false;
  for (const Eigen::Vector2d& p : dut.points_W) {
    if (std::abs(p.x()) < 0.05) through_gap = p.y() > 2.0 && p.y() < 3.0;
  }
  EXPECT_TRUE(through_gap);
  // an inflation of 0.5 m closes the 1 m gap: the goal is free but unreachable on a map that is
  // the whole operating area
  config.inflation_radius_m = 0.5;
  config.operating_area_W.emplace(Eigen::Vector2d(-5, -5), Eigen::Vector2d(5, 5));
  EXPECT_EQ(GridPlanner(map, config).Plan({-3, 0}, {3, 0}).status, PlanStatus::kNoPath);
}

TEST(AStarTest, AGoalWalledOffWithinTheMapIsMovedToTheMapsEdgeWhereTheWayGoesOn) {
  common::GridLayers map = EmptyMap();
  // a wall across the whole map at x = 0: within the map the goal is unreachable
  Paint(&map, 1.0f, [](const Eigen::Vector2d& p) { return std::abs(p.x()) < 0.15; });
  AStarConfig config;
  config.inflation_radius_m = 0.2;
  const Eigen::Vector2d start(-3, 2), goal(3, 1);
  const GridPath dut = GridPlanner(map, config).Plan(start, goal);
  ASSERT_EQ(dut.status, PlanStatus::kGoalMoved);
  // to the top edge beside the wall: of the edge cells, the least cost from the start plus the
  // straight line on to the goal at the unknown cells' cost (1 + 5 x 0.5 per metre)
  const Eigen::Vector2d edge_cell(-0.4, 5.0);
  EXPECT_NEAR((dut.goal_W - edge_cell).norm(), 0.0, 1e-9) << dut.goal_W.transpose();
  EXPECT_EQ(dut.points_W.back(), dut.goal_W);
  EXPECT_EQ(dut.points_W.front(), Eigen::Vector2d(-3.0, 2.0));
  // nothing beyond the edges: no way
  config.operating_area_W.emplace(Eigen::Vector2d(-5, -5), Eigen::Vector2d(5, 5));
  EXPECT_EQ(GridPlanner(map, config).Plan(start, goal).status, PlanStatus::kNoPath);
  // the world going on only beyond the bottom edge: the way leaves there
  config.operating_area_W.emplace(Eigen::Vector2d(-5, -8), Eigen::Vector2d(5, 5));
  const GridPath down = GridPlanner(map, config).Plan(start, goal);
  ASSERT_EQ(down.status, PlanStatus::kGoalMoved);
  EXPECT_NEAR((down.goal_W - Eigen::Vector2d(-0.4, -5.0)).norm(), 0.0, 1e-9)
      << down.goal_W.transpose();
  // unknown ground never entered: no way either
  config.operating_area_W.reset();
  config.unknown_policy = UnknownPolicy::kBlocked;
  EXPECT_EQ(GridPlanner(map, config).Plan(start, goal).status, PlanStatus::kNoPath);
}

TEST(AStarTest, AGoalOffTheMapBehindAWallIsApproachedAcrossTheMapsEdge) {
  common::GridLayers map = EmptyMap();
  AStarConfig config;
  config.inflation_radius_m = 0.2;
  const Eigen::Vector2d start(-3, 1), goal(9, 0);
  // nothing in the way: the reachable cell nearest to the goal, on the edge facing it
  const GridPath open = GridPlanner(map, config).Plan(start, goal);
  ASSERT_EQ(open.status, PlanStatus::kGoalMoved);
  EXPECT_EQ(open.goal_W, Eigen::Vector2d(5.0, 0.0));
  // a wall across the whole map at x = 2: the nearest reachable cell lies against it, a dead end;
  // the way goes on across the top edge beside the wall
  Paint(&map, 1.0f, [](const Eigen::Vector2d& p) { return std::abs(p.x() - 2.0) < 0.15; });
  const GridPath dut = GridPlanner(map, config).Plan(start, goal);
  ASSERT_EQ(dut.status, PlanStatus::kGoalMoved);
  EXPECT_NEAR((dut.goal_W - Eigen::Vector2d(1.6, 5.0)).norm(), 0.0, 1e-9) << dut.goal_W.transpose();
  // with nothing beyond the map but the goal's side, or the goal off the world, the nearest cell
  config.operating_area_W.emplace(Eigen::Vector2d(-5, -5), Eigen::Vector2d(12, 5));
  const GridPath walled = GridPlanner(map, config).Plan(start, goal);
  ASSERT_EQ(walled.status, PlanStatus::kGoalMoved);
  EXPECT_NEAR((walled.goal_W - Eigen::Vector2d(1.6, 0.0)).norm(), 0.0, 1e-9)
      << walled.goal_W.transpose();
  config.operating_area_W.emplace(Eigen::Vector2d(-5, -8), Eigen::Vector2d(8, 8));
  EXPECT_NEAR(
      (GridPlanner(map, config).Plan(start, goal).goal_W - Eigen::Vector2d(1.6, 0.0)).norm(), 0.0,
      1e-9);
}

// The map forgets what leaves it; the robot's memory (ObstacleMemory) does not.
TEST(AStarTest, AGoalBeyondARememberedDeadEndIsApproachedRoundIt) {
  AStarConfig config;
  config.inflation_radius_m = 0.2;
  config.operating_area_W.emplace(Eigen::Vector2d(-5, -8), Eigen::Vector2d(20, 8));
  const common::GridLayers map = EmptyMap();  // x and y in [-5, 5]
  const Eigen::Vector2d start(-3, 0), goal(14, 0);
  auto memory = std::make_shared<ObstacleMemory>(*config.operating_area_W, map.geometry());
  // a map seen before, 5 m on: a dead end 4.5 m deep and 3 m wide, open toward the map
  common::GridLayers seen(
      common::GridGeometry::Centered(Eigen::Vector2d(10, 0), Eigen::Vector2d(10, 10), 0.1),
      {"traversability"});
  seen.Layer("traversability").setZero();
  Paint(&seen, 1.0f, [](const Eigen::Vector2d& p) {
    const bool sides = p.x() > 5.5 && std::abs(std::abs(p.y()) - 1.5) < 0.11;
    const bool end = std::abs(p.x() - 10.0) < 0.11 && std::abs(p.y()) < 1.6;
    return sides || end;
  });
  memory->Record(seen.geometry(), seen.Layer("traversability"), config);
  auto plan = [&](std::shared_ptr<const ObstacleMemory> remembered) {
    const CostMap costs(map, config, std::move(remembered));
    return GridPlanner(costs.search()).Plan(start, goal);
  };
  // without the memory: the reachable cell nearest to the goal, into the dead end
  const GridPath forgetting = plan(nullptr);
  ASSERT_EQ(forgetting.status, PlanStatus::kGoalMoved);
  EXPECT_EQ(forgetting.goal_W, Eigen::Vector2d(5.0, 0.0));
  // with it: the same edge, beside the dead end's mouth, where the way on goes round it
  const GridPath remembering = plan(memory);
  ASSERT_EQ(remembering.status, PlanStatus::kGoalMoved);
  EXPECT_NEAR(remembering.goal_W.x(), 5.0, 1e-9);
  EXPECT_GT(std::abs(remembering.goal_W.y()), 1.6) << remembering.goal_W.transpose();
  EXPECT_LT(std::abs(remembering.goal_W.y()), 3.0) << remembering.goal_W.transpose();
  // seen open again, the dead end is forgotten
  seen.Layer("traversability").setZero();
  memory->Record(seen.geometry(), seen.Layer("traversability"), config);
  EXPECT_EQ(plan(memory).goal_W, Eigen::Vector2d(5.0, 0.0));
}

TEST(AStarTest, CostlyTerrainIsAvoidedInProportionToItsWeight) {
  common::GridLayers map = EmptyMap();
  // a rough band across the direct route, passable; a detour around it at y > 3
  Paint(&map, 0.6f, [](const Eigen::Vector2d& p) { return std::abs(p.x()) < 1.0 && p.y() < 3.0; });
  AStarConfig config;
  config.cost_weight = 0.0;  // cost ignored: straight through
  const GridPath ignoring = GridPlanner(map, config).Plan({-4, 0}, {4, 0});
  EXPECT_NEAR(Length(ignoring.points_W), 8.0, 1e-9);
  config.cost_weight = 10.0;  // 2 m at 1 + 6 = 7 per metre: the detour is cheaper
  const GridPath avoiding = GridPlanner(map, config).Plan({-4, 0}, {4, 0});
  double highest = -10.0;
  for (const Eigen::Vector2d& p : avoiding.points_W) highest = std::max(highest, p.y());
  EXPECT_GE(highest, 3.0 - 1e-9);
  EXPECT_LT(avoiding.cost, 8.0 * (1.0 + 10.0 * 0.6 * 2.0 / 8.0) + 1e-9);
}

TEST(AStarTest, UnknownCellsFollowThePolicy) {
  common::GridLayers map = EmptyMap();
  Paint(&map, std::numeric_limits<float>::quiet_NaN(),
        [](const Eigen::Vector2d& p) { return std::abs(p.x()) < 1.0; });
  AStarConfig config;
  config.unknown_policy = UnknownPolicy::kCost;
  EXPECT_EQ(GridPlanner(map, config).Plan({-4, 0}, {4, 0}).status, PlanStatus::kFound);
  config.unknown_policy = UnknownPolicy::kBlocked;
  EXPECT_EQ(GridPlanner(map, config).Plan({-4, 0}, {4, 0}).status, PlanStatus::kNoPath);
  // a goal inside the unknown band moves to its nearest reachable cell, at the band's edge
  const GridPath moved = GridPlanner(map, config).Plan({-4, 0}, {0.5, 0});
  EXPECT_EQ(moved.status, PlanStatus::kGoalMoved);
  EXPECT_NEAR(moved.goal_W.x(), -1.0, 0.05);
  EXPECT_NEAR(moved.goal_W.y(), 0.0, 1e-9);
}

TEST(AStarTest, ABlockedGoalMovesToTheNearestReachableCellAndABlockedStartIsAStatus) {
  common::GridLayers map = EmptyMap();
  Paint(&map, 1.0f,
        [](const Eigen::Vector2d& p) { return (p - Eigen::Vector2d(3, 0)).norm() < 0.5; });
  AStarConfig config;
  config.inflation_radius_m = 0.0;
  const GridPath dut = GridPlanner(map, config).Plan({-3, 0}, {3, 0});
  EXPECT_EQ(dut.status, PlanStatus::kGoalMoved);
  EXPECT_NEAR((dut.goal_W - Eigen::Vector2d(3, 0)).norm(), 0.5, 0.1);
  EXPECT_EQ(dut.points_W.back(), dut.goal_W);
  EXPECT_EQ(GridPlanner(map, config).Plan({3, 0}, {-3, 0}).status, PlanStatus::kStartBlocked);
  EXPECT_EQ(GridPlanner(map, config).Plan({30, 0}, {-3, 0}).status, PlanStatus::kStartBlocked);
}

TEST(AStarTest, SimplificationKeepsLineOfSightAndTheEnds) {
  common::GridLayers map = EmptyMap();
  Paint(&map, 1.0f, [](const Eigen::Vector2d& p) { return std::abs(p.x()) < 0.15 && p.y() < 2.0; });
  AStarConfig config;
  config.inflation_radius_m = 0.2;
  const GridPlanner planner(map, config);
  const GridPath path = planner.Plan({-3, 0}, {3, 0});
  const std::vector<Eigen::Vector2d> waypoints = planner.Simplify(path.points_W);
  EXPECT_EQ(waypoints.front(), path.points_W.front());
  EXPECT_EQ(waypoints.back(), path.points_W.back());
  EXPECT_LT(waypoints.size(), 6u);
  EXPECT_GE(waypoints.size(), 3u);  // it must turn around the wall's end
  // every segment keeps clear of the wall's cells (|x| <= 0.1, y <= 1.9) by the inflation less a
  // cell
  for (std::size_t i = 1; i < waypoints.size(); ++i) {
    for (double t = 0.0; t <= 1.0; t += 0.01) {
      const Eigen::Vector2d p = waypoints[i - 1] + t * (waypoints[i] - waypoints[i - 1]);
      const Eigen::Vector2d nearest(std::clamp(p.x(), -0.1, 0.1), std::min(p.y(), 1.9));
      EXPECT_GE((p - nearest).norm(), 0.1) << p.transpose();
    }
  }
}

}  // namespace
}  // namespace trav::planner
