#include "planner/navigation_planner.h"

#include <optional>
#include <vector>

#include "planner_test_util.h"
#include <gtest/gtest.h>

#include "common/enum_names.h"
#include "common/random.h"
#include "planner/cost_field.h"
#include "planner/manoeuvres.h"

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
  // the map is the whole operating area
  NavigationPlannerConfig config;
  config.search.operating_area_W.emplace(Eigen::Vector2d(-6, -6), Eigen::Vector2d(14, 6));
  NavigationPlanner dut(config);
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
  // where the world goes on beyond the map, the way may too: to the map's edge nearer to the
  // start, the top one for a start 1 m above the middle and the bottom one for 1 m below
  for (const double start_y : {1.0, -1.0}) {
    common::TrajectoryPoint start = Start();
    start.position_W.y() = start_y;
    NavigationPlanner in_a_larger_world(NavigationPlannerConfig{});
    const NavigationPlan beyond = in_a_larger_world.Plan(map, start, {9.0, 0.0}, {});
    EXPECT_EQ(beyond.status, NavigationStatus::kPlannedToNearest);
    EXPECT_TRUE(beyond.has_trajectory());
    const Eigen::Vector2d end = beyond.waypoints_W.back();
    EXPECT_LT(end.x(), 4.0);
    EXPECT_NEAR(end.y(), 6.0 * start_y, 1e-9) << end.transpose();
  }
}

TEST(NavigationPlannerTest, RemembersTheObstaclesOfTheMapsItWasGivenWithinTheOperatingArea) {
  const common::GridLayers map = WallMap();
  // without an operating area, nothing
  NavigationPlanner unbounded{NavigationPlannerConfig{}};
  EXPECT_EQ(unbounded.Remember(map), nullptr);
  NavigationPlannerConfig config;
  config.search.operating_area_W.emplace(Eigen::Vector2d(-20, -20), Eigen::Vector2d(40, 20));
  NavigationPlanner dut(config);
  const std::shared_ptr<const ObstacleMemory> first = dut.Remember(map);
  ASSERT_NE(first, nullptr);
  EXPECT_TRUE(first->Blocked({4.3, 0.0}));
  EXPECT_FALSE(first->Blocked({4.3, 3.0}));
  EXPECT_FALSE(first->Blocked({-10.0, 0.0}));
  // the map rolled 20 m on: the wall has left it, the memory keeps it; what the new map shows is
  // added to a new memory, and the one given before stays as it was
  common::GridLayers rolled = map;
  rolled.Recenter(Eigen::Vector2d(24, 0));
  test_util::Paint(&rolled, 1.0f,
                   [](const Eigen::Vector2d& p) { return std::abs(p.x() - 25.0) < 0.1; });
  const std::shared_ptr<const ObstacleMemory> second = dut.Remember(rolled);
  EXPECT_TRUE(second->Blocked({4.3, 0.0}));
  EXPECT_TRUE(second->Blocked({25.0, 3.0}));
  EXPECT_FALSE(first->Blocked({25.0, 3.0}));
  // Reset forgets
  dut.Reset();
  EXPECT_FALSE(dut.Remember(rolled)->Blocked({4.3, 0.0}));
}

// The smallest gap between the footprint and lethal cells along a trajectory, and at its start [m].
std::pair<double, double> FootprintGaps(const common::GridLayers& map,
                                        const NavigationPlannerConfig& config,
                                        const common::Trajectory& trajectory) {
  const CostField field(map, config.SearchConfig());
  const std::vector<Eigen::Vector2d> body_B =
      config.footprint.BoundaryPoints_B(map.geometry().resolution_m);
  double smallest = std::numeric_limits<double>::infinity();
  for (const common::TrajectoryPoint& p : trajectory.points()) {
    smallest = std::min(smallest, FootprintDistance(field, p.position_W, p.yaw, body_B));
  }
  const common::TrajectoryPoint& first = trajectory.points().front();
  return {smallest, FootprintDistance(field, first.position_W, first.yaw, body_B)};
}

// 12 x 8 m at 0.2 m (the mappers' resolution), cost 0.1, with `boxes` random lethal boxes of 0.2
// to 2.4 m by 0.2 to 0.6 m (walls and columns), none over the start (-5, 0) or the goal (5, 0).
common::GridLayers RandomWorld(std::uint64_t seed, int boxes) {
  common::GridLayers map(
      common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(12, 8), 0.2),
      {"traversability"});
  map.Layer("traversability").setConstant(0.1f);
  common::Random random(seed);
  for (int b = 0; b < boxes; ++b) {
    const Eigen::Vector2d centre(random.Uniform(-4.0, 4.0), random.Uniform(-3.5, 3.5));
    Eigen::Vector2d half(random.Uniform(0.1, 1.2), random.Uniform(0.1, 0.3));
    if (random.Uniform(0.0, 1.0) < 0.5) std::swap(half.x(), half.y());
    test_util::Paint(&map, 1.0f, [&](const Eigen::Vector2d& p) {
      return ((p - centre).cwiseAbs() - half).maxCoeff() <= 0.0 &&
             (p - Eigen::Vector2d(-5, 0)).norm() > 0.8 && (p - Eigen::Vector2d(5, 0)).norm() > 0.8;
    });
  }
  return map;
}

// The relation of the footprint model (docs/navigation.md): whatever path A* admits, the planner
// returns a trajectory, optimised or one of the fallbacks, and the footprint never comes closer
// to lethal cells along it than the smallest clearance (or than it started), up to the
// optimiser's 5 % tolerance on a 0.2 m cell.
TEST(NavigationPlannerTest, EveryPathTheSearchAdmitsYieldsATrajectoryThatKeepsTheFootprintClear) {
  const NavigationPlannerConfig config;
  const double tolerance_m = config.optimizer.violation_tolerance * 0.2;
  int paths = 0, tight = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    const common::GridLayers map = RandomWorld(seed, 14);
    common::TrajectoryPoint start;
    start.position_W = Eigen::Vector2d(-5, 0);
    start.yaw = 0.5 * static_cast<double>(seed);  // any heading
    NavigationPlanner dut(config);
    const NavigationPlan plan = dut.Plan(map, start, {5, 0}, {});
    if (plan.status == NavigationStatus::kNoPath) continue;
    ++paths;
    ASSERT_TRUE(plan.has_trajectory()) << "seed " << seed;
    const bool leads_to_goal = plan.status == NavigationStatus::kPlanned ||
                               plan.status == NavigationStatus::kPlannedToNearest;
    ASSERT_TRUE(leads_to_goal || plan.fallback != Fallback::kNone)
        << "seed " << seed << ": " << plan.optimized.diagnostics.worst_constraint;
    const auto [smallest_m, start_m] = FootprintGaps(map, config, plan.optimized.trajectory);
    EXPECT_GE(smallest_m, std::min(config.optimizer.min_clearance_m, start_m) - tolerance_m)
        << "seed " << seed << " fallback " << common::NameOf(plan.fallback);
    tight += smallest_m < config.optimizer.clearance_m ? 1 : 0;
  }
  // the worlds leave most routes open, and many pass closer than the desired clearance
  EXPECT_GE(paths, 30);
  EXPECT_GE(tight, 10);
}

// With one L-BFGS iteration and a micrometre of end tolerance the optimiser cannot converge, so
// the planner falls back.
NavigationPlannerConfig OneIteration() {
  NavigationPlannerConfig config;
  config.optimizer.max_iterations = 1;
  config.optimizer.terminal_tolerance_m = 1e-6;
  return config;
}

TEST(NavigationPlannerTest, AFailedOptimisationFollowsTheSearchPathAtCreepSpeed) {
  const NavigationPlannerConfig config = OneIteration();
  NavigationPlanner dut(config);
  // a wall across the way with a 1.0 m gap: too narrow for a path on which the robot can turn
  // (the wider margin's 2 x (0.423 + 0.1) m), wide enough for the robot
  common::GridLayers map = WallMap();
  test_util::Paint(&map, 0.1f, [](const Eigen::Vector2d&) { return true; });
  test_util::Paint(&map, 1.0f, [](const Eigen::Vector2d& p) {
    return p.x() >= 4.0 && p.x() <= 4.6 && std::abs(p.y()) > 0.5;
  });
  const NavigationPlan plan = dut.Plan(map, Start(), {9.0, 0.0}, {});
  ASSERT_EQ(plan.fallback, Fallback::kFollowPath);
  EXPECT_EQ(plan.status, NavigationStatus::kPlanned);
  const common::Trajectory& t = plan.optimized.trajectory;
  EXPECT_LE((t.points().back().position_W - Eigen::Vector2d(9.0, 0.0)).norm(), 1e-9);
  for (const common::TrajectoryPoint& p : t.points()) {
    EXPECT_LE(std::abs(p.v), config.fallback.creep_speed_m_s);
    EXPECT_LE(std::abs(p.omega), config.fallback.creep_yaw_rate_rad_s);
  }
  EXPECT_GE(FootprintGaps(map, config, t).first, config.optimizer.min_clearance_m);
}

TEST(NavigationPlannerTest, AFailedOptimisationTakesAWiderWayOptimisedWhereThereIsOne) {
  NavigationPlanner dut{NavigationPlannerConfig{}};
  // the wall of WallMap with a 0.9 m gap on the straight way: A* takes the gap, too narrow for the
  // wider margin's search (2 x (0.423 + 0.1) m); a walker stands in it, which the search does not
  // see and the optimiser cannot pass; round the wall's end the way is open
  common::GridLayers map = WallMap();
  test_util::Paint(&map, 0.1f, [](const Eigen::Vector2d& p) {
    return p.x() >= 4.0 && p.x() <= 4.6 && std::abs(p.y()) < 0.45;
  });
  const MovingObstacle walker{Eigen::Vector2d(4.3, 0.0), Eigen::Vector2d::Zero(), 0.3, Start().t_s};
  const NavigationPlan plan = dut.Plan(map, Start(), {9.0, 0.0}, {walker});
  bool through_gap = false;
  for (const Eigen::Vector2d& p : plan.path.points_W) {
    through_gap = through_gap || (std::abs(p.x() - 4.3) < 0.3 && std::abs(p.y()) < 0.45);
  }
  EXPECT_TRUE(through_gap);
  ASSERT_EQ(plan.fallback, Fallback::kWiderMargin) << common::NameOf(plan.status);
  EXPECT_NE(plan.optimized.status, OptimizationStatus::kInfeasible);
  EXPECT_EQ(plan.status, NavigationStatus::kPlanned);
  // optimised round the wall's end (y > 2) to the goal
  double highest_y = -1.0;
  for (const common::TrajectoryPoint& p : plan.optimized.trajectory.points()) {
    highest_y = std::max(highest_y, p.position_W.y());
  }
  EXPECT_GT(highest_y, 2.0);
  EXPECT_LE((plan.optimized.trajectory.points().back().position_W - Eigen::Vector2d(9, 0)).norm(),
            0.1);
}

TEST(NavigationPlannerTest, WithoutAPathToFollowAndThePoseSearchARobotTurnsTowardThePath) {
  NavigationPlannerConfig config = OneIteration();
  config.fallback.search_expansions = 0;
  NavigationPlanner dut(config);
  // a wall across the world with a 0.7 m gap: the search path goes through it, too close to the
  // jambs to be followed without optimisation (0.065 m against optimizer.clearance)
  common::GridLayers map = WallMap();
  test_util::Paint(&map, 0.1f, [](const Eigen::Vector2d&) { return true; });
  test_util::Paint(&map, 1.0f, [](const Eigen::Vector2d& p) {
    return p.x() >= 4.0 && p.x() <= 4.6 && std::abs(p.y()) > 0.35;
  });
  common::TrajectoryPoint start = Start();
  start.yaw = 0.5 * M_PI;  // facing across the way
  const NavigationPlan plan = dut.Plan(map, start, {9.0, 0.0}, {});
  ASSERT_EQ(plan.fallback, Fallback::kTurnInPlace) << common::NameOf(plan.status);
  EXPECT_EQ(plan.status, NavigationStatus::kOptimizerFailed);  // it only frees the robot
  const common::Trajectory& t = plan.optimized.trajectory;
  const Eigen::Vector2d towards = plan.waypoints_W[1] - start.position_W;
  EXPECT_NEAR(t.points().back().yaw, std::atan2(towards.y(), towards.x()), 1e-9);
  for (const common::TrajectoryPoint& p : t.points()) {
    EXPECT_EQ(p.position_W, start.position_W);
    EXPECT_LE(std::abs(p.omega), config.fallback.creep_yaw_rate_rad_s + 1e-12);
  }
}

// A dead end 0.8 m wide (cells of 0.1 m) closed at x = 1: too narrow to turn the 0.85 m
// circumscribed disc in.
common::GridLayers DeadEndMap() {
  common::GridLayers map = WallMap();
  test_util::Paint(&map, 0.1f, [](const Eigen::Vector2d&) { return true; });
  test_util::Paint(&map, 1.0f, [](const Eigen::Vector2d& p) {
    return p.x() > -3.0 && p.x() < 1.2 && (std::abs(p.y()) > 0.4 || p.x() > 1.0) &&
           std::abs(p.y()) < 0.7;
  });
  return map;
}

common::TrajectoryPoint AtTheEndOfTheDeadEnd() {
  common::TrajectoryPoint start;
  start.position_W = Eigen::Vector2d(0.55, 0.0);  // the front 0.137 m from the end
  return start;
}

TEST(NavigationPlannerTest, ARobotFacingTheEndOfANarrowDeadEndReversesOutOfIt) {
  // the goal lies behind the robot: following the search path would turn in the dead end
  const common::GridLayers map = DeadEndMap();
  const NavigationPlannerConfig config = OneIteration();
  NavigationPlanner dut(config);
  const NavigationPlan plan = dut.Plan(map, AtTheEndOfTheDeadEnd(), {-5.5, 0.0}, {});
  ASSERT_EQ(plan.fallback, Fallback::kPoseSearch) << common::NameOf(plan.status);
  EXPECT_EQ(plan.status, NavigationStatus::kPlanned);  // on its way to the goal
  const common::Trajectory& t = plan.optimized.trajectory;
  // backward along the dead end without turning, to the search path's point 4 m along
  EXPECT_NEAR(t.points().back().position_W.x(), 0.55 - config.fallback.search_reach_m, 0.1);
  EXPECT_EQ(t.points().back().yaw, 0.0);
  EXPECT_EQ(t.Sample(0.5).v, -config.fallback.creep_speed_m_s);
  // followed without periodic replans over its first metre, narrow throughout
  ASSERT_TRUE(plan.commit_until_s.has_value());
  EXPECT_NEAR(t.Sample(*plan.commit_until_s).position_W.x(), 0.55 - 1.0, 0.01);
  EXPECT_GE(FootprintGaps(map, config, t).first,
            std::min(config.optimizer.clearance_m, FootprintGaps(map, config, t).second) - 1e-9);
}

TEST(NavigationPlannerTest, WithoutThePoseSearchARobotFacingTheEndOfADeadEndBacksOut) {
  const common::GridLayers map = DeadEndMap();
  NavigationPlannerConfig config = OneIteration();
  config.fallback.search_expansions = 0;
  NavigationPlanner dut(config);
  const NavigationPlan plan = dut.Plan(map, AtTheEndOfTheDeadEnd(), {-5.5, 0.0}, {});
  ASSERT_EQ(plan.fallback, Fallback::kBackOut) << common::NameOf(plan.status);
  EXPECT_EQ(plan.status, NavigationStatus::kOptimizerFailed);
  const common::Trajectory& t = plan.optimized.trajectory;
  EXPECT_NEAR(t.points().back().position_W.x(), 0.55 - config.fallback.back_out_distance_m, 1e-9);
  EXPECT_EQ(t.points().back().yaw, 0.0);
  EXPECT_LT(t.Sample(0.5).v, 0.0);
}

// A robot still faster than the manoeuvres go stops first, straight along its heading at the
// tracker's deceleration (the planner's default: the MPC's 2 m/s^2); at creep speed it takes them.
TEST(NavigationPlannerTest, AFailedOptimisationAtSpeedStopsBeforeTheManoeuvres) {
  const common::GridLayers map = DeadEndMap();
  const NavigationPlannerConfig config = OneIteration();
  NavigationPlanner dut(config);
  common::TrajectoryPoint start = AtTheEndOfTheDeadEnd();
  start.v = -0.5;  // reversing: 0.25 s and 0.0625 m to rest
  const NavigationPlan plan = dut.Plan(map, start, {-5.5, 0.0}, {});
  ASSERT_EQ(plan.fallback, Fallback::kStop) << common::NameOf(plan.status);
  EXPECT_EQ(plan.status, NavigationStatus::kOptimizerFailed);  // not a plan to the goal
  const common::Trajectory& t = plan.optimized.trajectory;
  EXPECT_NEAR(t.end_time() - t.start_time(), 0.25, 1e-12);
  EXPECT_NEAR(t.points().back().position_W.x(), 0.55 - 0.0625, 1e-12);
  EXPECT_EQ(t.points().back().v, 0.0);
  start.v = -config.fallback.creep_speed_m_s;
  EXPECT_EQ(dut.Plan(map, start, {-5.5, 0.0}, {}).fallback, Fallback::kPoseSearch);
}

// Turning onto a 1.2 m corridor's straight at 1.2 m/s when the optimisation fails: the stop brakes
// along the trajectory the robot follows, which straightens, where the heading's arc would keep
// turning toward the wall.
TEST(NavigationPlannerTest, AStopAtSpeedBrakesAlongTheFollowedPathWhenItKeepsFartherFromObstacles) {
  common::GridLayers map = WallMap();
  test_util::Paint(&map, 0.1f, [](const Eigen::Vector2d&) { return true; });
  test_util::Paint(&map, 1.0f, [](const Eigen::Vector2d& p) { return std::abs(p.y()) > 0.55; });
  const NavigationPlannerConfig config = OneIteration();
  const common::Trajectory followed = test_util::TurnThenStraight(1.0, 1.2, 0.05, 2.0, 3.0);
  const common::TrajectoryPoint start = followed.Sample(1.0);
  NavigationPlanner dut(config);
  const NavigationPlan along = dut.Plan(map, start, {5.0, 0.0}, {}, &followed);
  ASSERT_EQ(along.fallback, Fallback::kStop) << common::NameOf(along.status);
  EXPECT_EQ(along.status, NavigationStatus::kOptimizerFailed);
  const std::optional<common::Trajectory> expected = StopAlong(followed, start, config.fallback);
  ASSERT_TRUE(expected.has_value());
  EXPECT_EQ(along.optimized.trajectory.points().back().position_W,
            expected->points().back().position_W);
  // without the followed trajectory: the arc, which ends closer to the wall
  const NavigationPlan arc = dut.Plan(map, start, {5.0, 0.0}, {});
  ASSERT_EQ(arc.fallback, Fallback::kStop);
  EXPECT_NEAR(arc.optimized.trajectory.points().back().yaw, 0.6, 1e-12);
  const CostField field(map, config.SearchConfig());
  const std::vector<Eigen::Vector2d> body = config.footprint.BoundaryPoints_B(0.1);
  EXPECT_GT(SmallestGap(field, along.optimized.trajectory, body), 0.15);
  EXPECT_LT(SmallestGap(field, arc.optimized.trajectory, body), 0.08);
}

}  // namespace
}  // namespace trav::planner
