#include "planner/trajectory_optimizer.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "common/input_error.h"
#include "tests/planner/planner_test_util.h"

namespace trav::planner {
namespace {

using test_util::Paint;

// 16 x 10 m at 0.1 m with cost `cost` everywhere.
common::GridLayers FlatMap(float cost = 0.0f) {
  common::GridLayers map(
      common::GridGeometry::Centered(Eigen::Vector2d(5, 0), Eigen::Vector2d(16, 10), 0.1),
      {"traversability"});
  map.Layer("traversability").setConstant(cost);
  return map;
}

TrajectoryRequest StraightRequest() {
  TrajectoryRequest request;
  request.start.t_s = 2.0;
  request.start.position_W = Eigen::Vector2d(0, 0);
  request.goal_W = Eigen::Vector2d(10, 0);
  return request;
}

// Largest |v|, |omega|, |a| over the trajectory.
struct Extremes {
  double v{0.0}, omega{0.0}, a{0.0};
};
Extremes ExtremesOf(const common::Trajectory& trajectory) {
  Extremes e;
  for (const common::TrajectoryPoint& p : trajectory.points()) {
    e.v = std::max(e.v, std::abs(p.v));
    e.omega = std::max(e.omega, std::abs(p.omega));
    e.a = std::max(e.a, std::abs(p.acceleration));
  }
  return e;
}

TEST(TrajectoryOptimizerTest, DrivesStraightToTheGoalWithinTheLimits) {
  const common::GridLayers map = FlatMap();
  const CostField field(map, CostMapConfig{});
  TrajectoryOptimizerConfig config;
  TrajectoryOptimizer dut(config);
  const OptimizedTrajectory out = dut.Optimize(field, StraightRequest());
  ASSERT_EQ(out.status, OptimizationStatus::kConverged) << out.diagnostics.worst_constraint;
  const common::Trajectory& t = out.trajectory;
  EXPECT_EQ(t.start_time(), 2.0);
  EXPECT_EQ(t.points().front().position_W, Eigen::Vector2d(0, 0));
  EXPECT_LE((t.points().back().position_W - Eigen::Vector2d(10, 0)).norm(),
            config.terminal_tolerance_m);
  EXPECT_NEAR(t.points().back().v, 0.0, 1e-9);
  const Extremes e = ExtremesOf(t);
  EXPECT_LE(e.v, 1.05 * config.limits.max_speed_m_s);
  EXPECT_LE(e.a, 1.05 * config.limits.max_acceleration_m_s2);
  // close to the time-optimal straight run (10 m at 1.5 m/s with 1.5 m/s^2 ramps: 7.67 s)
  EXPECT_GT(e.v, 0.9 * config.limits.max_speed_m_s);
  EXPECT_LT(t.end_time() - t.start_time(), 10.0);
  for (const common::TrajectoryPoint& p : t.points()) EXPECT_NEAR(p.position_W.y(), 0.0, 0.02);
  EXPECT_LE(out.diagnostics.max_violation, config.violation_tolerance);
  EXPECT_GT(out.diagnostics.iterations, 0);
  EXPECT_GT(out.diagnostics.costs.energy, 0.0);
  EXPECT_GT(out.diagnostics.costs.time, 0.0);
}

TEST(TrajectoryOptimizerTest, SlowsToTheTerrainsLimitOverARoughBandAndOnlyThere) {
  // a curb across the route: roughness 0.06 m on the cells at 4.9 <= x <= 5.1, no other roughness
  common::GridLayers map = FlatMap();
  map.AddLayer("roughness");
  const common::GridGeometry& g = map.geometry();
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      map.Layer("roughness")(ix, iy) =
          std::abs(g.CellCenter(ix, iy).x() - 5.0) < 0.15 ? 0.06f : 0.0f;
    }
  }
  CostMapConfig fields;
  fields.speed.reach_m = 0.4;  // the limit holds for the base within 0.4 m of the band
  const CostField field(map, fields);
  TrajectoryOptimizerConfig config;
  TrajectoryOptimizer dut(config);
  const OptimizedTrajectory out = dut.Optimize(field, StraightRequest());
  ASSERT_EQ(out.status, OptimizationStatus::kConverged) << out.diagnostics.worst_constraint;
  double fastest_on_band = 0.0, fastest_before = 0.0, fastest_after = 0.0;
  for (const common::TrajectoryPoint& p : out.trajectory.points()) {
    const double x = p.position_W.x();
    if (std::abs(x - 5.0) <= 0.5) fastest_on_band = std::max(fastest_on_band, std::abs(p.v));
    if (x < 3.0) fastest_before = std::max(fastest_before, std::abs(p.v));
    if (x > 7.0) fastest_after = std::max(fastest_after, std::abs(p.v));
  }
  // within 5 % of the rough speed over the band and its reach; close to the open speed away
  EXPECT_LE(fastest_on_band, 1.05 * fields.speed.rough_m_s);
  EXPECT_GT(fastest_before, 1.3);
  EXPECT_GT(fastest_after, 1.3);
  // without the roughness layer the same request crosses at full speed
  const OptimizedTrajectory open =
      TrajectoryOptimizer(config).Optimize(CostField(FlatMap(), fields), StraightRequest());
  double fastest_open = 0.0;
  for (const common::TrajectoryPoint& p : open.trajectory.points()) {
    if (std::abs(p.position_W.x() - 5.0) <= 0.5) fastest_open = std::max(fastest_open, p.v);
  }
  EXPECT_GT(fastest_open, 1.1 * fields.speed.rough_m_s);
}

TEST(TrajectoryOptimizerTest, CrossesAClimbableStepSquareWhereTheStraightLineMeetsItAskew) {
  // a 0.13 m step up along x = 5 (roughness: common::Roughness of the heights), met by the straight
  // line from (2, -2) to (8, 2) at 34 deg from square
  common::GridLayers map = FlatMap();
  test_util::PaintRoughness(&map,
                            [](const Eigen::Vector2d& p) { return p.x() > 5.0 ? 0.13 : 0.0; });
  TrajectoryRequest request;
  request.start.t_s = 0.0;
  request.start.position_W = Eigen::Vector2d(2, -2);
  request.start.yaw = std::atan2(4.0, 6.0);
  request.goal_W = Eigen::Vector2d(8, 2);
  // the largest angle from square while the base is within 0.3 m of the edge
  auto askew_deg = [&](double max_angle_deg) {
    CostMapConfig fields;
    fields.steps.reach_m = 0.4;
    fields.steps.max_angle_deg = max_angle_deg;
    const OptimizedTrajectory out =
        TrajectoryOptimizer(TrajectoryOptimizerConfig{}).Optimize(CostField(map, fields), request);
    EXPECT_EQ(out.status, OptimizationStatus::kConverged) << out.diagnostics.worst_constraint;
    double largest = 0.0;
    for (const common::TrajectoryPoint& p : out.trajectory.points()) {
      if (std::abs(p.position_W.x() - 5.0) > 0.3) continue;
      largest = std::max(largest, std::abs(std::remainder(p.yaw, M_PI)) * 180.0 / M_PI);
    }
    return largest;
  };
  EXPECT_LT(askew_deg(15.0), 18.0);
  EXPECT_GT(askew_deg(90.0), 25.0);
}

TEST(TrajectoryOptimizerTest, KeepsClearOfLethalCellsAlongTheGuide) {
  // a wall from y = -5 to y = 1 at x in [4, 5]: the guide goes around its top end
  common::GridLayers map = FlatMap();
  Paint(&map, 1.0f, [](const Eigen::Vector2d& p) { return p.x() >= 4 && p.x() <= 5 && p.y() < 1; });
  const CostField field(map, CostMapConfig{});
  TrajectoryOptimizerConfig config;
  TrajectoryOptimizer dut(config);
  TrajectoryRequest request = StraightRequest();
  request.guide_W = {{0, 0}, {3.5, 1.8}, {5.5, 1.8}, {10, 0}};
  const OptimizedTrajectory out = dut.Optimize(field, request);
  ASSERT_EQ(out.status, OptimizationStatus::kConverged) << out.diagnostics.worst_constraint;
  EXPECT_GE(out.diagnostics.min_clearance_m, 0.95 * config.clearance_m);
  for (const common::TrajectoryPoint& p : out.trajectory.points()) {
    EXPECT_GE(field.Distance(p.position_W).value, 0.95 * config.clearance_m) << p.t_s;
  }
  const Extremes e = ExtremesOf(out.trajectory);
  EXPECT_LE(e.v, 1.05 * config.limits.max_speed_m_s);
  EXPECT_LE(e.omega, 1.05 * config.limits.max_yaw_rate_rad_s);
  EXPECT_LE(e.a, 1.05 * config.limits.max_acceleration_m_s2);
}

TEST(TrajectoryOptimizerTest, AGapNarrowerThanTheClearanceIsPassedAtTheMinimumClearance) {
  // walls across x in [4, 5] leave a 0.97 m gap around y = 0 (0.9 m between the cells' faces):
  // the Scout Mini's 0.57 m wide footprint cannot keep 0.3 m from them in it, 0.1 m it can
  common::GridLayers map = FlatMap();
  Paint(&map, 1.0f, [](const Eigen::Vector2d& p) {
    return p.x() >= 4 && p.x() <= 5 && std::abs(p.y()) > 0.485;
  });
  const CostField field(map, CostMapConfig{});
  TrajectoryOptimizerConfig config;
  config.clearance_m = 0.3;
  config.min_clearance_m = 0.3;
  TrajectoryRequest request = StraightRequest();
  request.guide_W = {{0, 0}, {10, 0}};
  EXPECT_EQ(TrajectoryOptimizer(config).Optimize(field, request).status,
            OptimizationStatus::kInfeasible);

  config.min_clearance_m = 0.1;
  const OptimizedTrajectory out = TrajectoryOptimizer(config).Optimize(field, request);
  ASSERT_NE(out.status, OptimizationStatus::kInfeasible) << out.diagnostics.worst_constraint;
  EXPECT_EQ(out.diagnostics.clearance_m, 0.1);
  EXPECT_GE(out.diagnostics.min_clearance_m, 0.1 - config.violation_tolerance * 0.3);
  EXPECT_LE((out.trajectory.points().back().position_W - request.goal_W).norm(),
            10.0 * config.terminal_tolerance_m);
}

TEST(TrajectoryOptimizerTest, AMoverCrossingThePathIsGivenItsClearanceAtEveryTime) {
  const common::GridLayers map = FlatMap();
  const CostField field(map, CostMapConfig{});
  TrajectoryOptimizerConfig config;
  TrajectoryRequest request = StraightRequest();
  // without the mover the robot passes x = 5 about 4 s after the start: the mover, walking +y at
  // 0.8 m/s, is there then
  const MovingObstacle mover{Eigen::Vector2d(5, -3.2), Eigen::Vector2d(0, 0.8), 0.3, 2.0};
  request.obstacles = {mover};
  TrajectoryOptimizer dut(config);
  const OptimizedTrajectory out = dut.Optimize(field, request);
  ASSERT_NE(out.status, OptimizationStatus::kInfeasible) << out.diagnostics.worst_constraint;
  double min_gap = 1e9;
  for (const common::TrajectoryPoint& p : out.trajectory.points()) {
    const double gap =
        (p.position_W - mover.PositionAt(p.t_s)).norm() - config.robot_radius_m - mover.radius_m;
    min_gap = std::min(min_gap, gap);
  }
  EXPECT_GE(min_gap, 0.95 * config.obstacle_clearance_m);
  EXPECT_NEAR(min_gap, out.diagnostics.min_obstacle_gap_m, 1e-12);
  // and the plan without the mover would have hit it
  TrajectoryOptimizer blind(config);
  request.obstacles.clear();
  const OptimizedTrajectory naive = blind.Optimize(field, request);
  double naive_gap = 1e9;
  for (const common::TrajectoryPoint& p : naive.trajectory.points()) {
    naive_gap = std::min(naive_gap, (p.position_W - mover.PositionAt(p.t_s)).norm() -
                                        config.robot_radius_m - mover.radius_m);
  }
  EXPECT_LT(naive_gap, 0.0);
}

TEST(TrajectoryOptimizerTest, TraversabilityCostPullsTheTrajectoryOffARidge) {
  // a costly ridge along y = -0.3: the traversability term moves the middle of the run off it
  common::GridLayers map = FlatMap();
  const common::GridGeometry& g = map.geometry();
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      const double y = g.CellCenter(ix, iy).y() + 0.3;
      map.Layer("traversability")(ix, iy) = static_cast<float>(0.7 * std::exp(-y * y / 2.0));
    }
  }
  const CostField field(map, CostMapConfig{});
  auto middle_y = [&](double weight) {
    TrajectoryOptimizerConfig config;
    config.weights.traversability = weight;
    TrajectoryOptimizer dut(config);
    const OptimizedTrajectory out = dut.Optimize(field, StraightRequest());
    EXPECT_NE(out.status, OptimizationStatus::kInfeasible);
    const common::Trajectory& t = out.trajectory;
    return t.Sample(0.5 * (t.start_time() + t.end_time())).position_W.y();
  };
  EXPECT_NEAR(middle_y(0.0), 0.0, 0.02);
  EXPECT_GT(middle_y(200.0), 0.3);
}

TEST(TrajectoryOptimizerTest, SameInputsGiveTheSameTrajectory) {
  common::GridLayers map = FlatMap(0.2f);
  Paint(&map, 1.0f,
        [](const Eigen::Vector2d& p) { return (p - Eigen::Vector2d(5, 0.4)).norm() < 0.7; });
  const CostField field(map, CostMapConfig{});
  TrajectoryRequest request = StraightRequest();
  request.guide_W = {{0, 0}, {5, -1.5}, {10, 0}};
  request.obstacles = {{Eigen::Vector2d(8, 3), Eigen::Vector2d(0, -0.5), 0.3, 2.0}};
  const OptimizedTrajectory a =
      TrajectoryOptimizer(TrajectoryOptimizerConfig{}).Optimize(field, request);
  const OptimizedTrajectory b =
      TrajectoryOptimizer(TrajectoryOptimizerConfig{}).Optimize(field, request);
  ASSERT_EQ(a.trajectory.points().size(), b.trajectory.points().size());
  for (std::size_t i = 0; i < a.trajectory.points().size(); ++i) {
    EXPECT_EQ(a.trajectory.points()[i].position_W, b.trajectory.points()[i].position_W);
    EXPECT_EQ(a.trajectory.points()[i].yaw, b.trajectory.points()[i].yaw);
    EXPECT_EQ(a.trajectory.points()[i].v, b.trajectory.points()[i].v);
  }
  EXPECT_EQ(a.diagnostics.iterations, b.diagnostics.iterations);
}

TEST(TrajectoryOptimizerTest, ReplanningTowardTheSameGoalStartsFromThePreviousPlan) {
  const common::GridLayers map = FlatMap();
  const CostField field(map, CostMapConfig{});
  TrajectoryOptimizer dut(TrajectoryOptimizerConfig{});
  const OptimizedTrajectory first = dut.Optimize(field, StraightRequest());
  ASSERT_FALSE(first.diagnostics.warm_started);
  TrajectoryRequest request = StraightRequest();
  request.start = first.trajectory.Sample(3.0);
  const OptimizedTrajectory second = dut.Optimize(field, request);
  EXPECT_TRUE(second.diagnostics.warm_started);
  EXPECT_EQ(second.status, OptimizationStatus::kConverged);
  // the replanned trajectory continues the first one
  EXPECT_NEAR(second.trajectory.end_time(), first.trajectory.end_time(), 0.3);
  EXPECT_LT(
      (second.trajectory.Sample(4.0).position_W - first.trajectory.Sample(4.0).position_W).norm(),
      0.1);
  // a different goal starts cold
  request.goal_W = Eigen::Vector2d(10, 3);
  EXPECT_FALSE(dut.Optimize(field, request).diagnostics.warm_started);
}

TEST(TrajectoryOptimizerTest, AStartOverlappingALethalCellLeavesItAndKeepsItsGapBelowZero) {
  // a 1 m strip of lethal cells (y in [0.25, 0.35]) that the footprint's left side (0.285 m from
  // the base) reaches into at the start: the way out keeps the start's gap less 15 % of its size
  common::GridLayers map = FlatMap();
  Paint(&map, 1.0f, [](const Eigen::Vector2d& p) {
    return std::abs(p.x()) < 0.5 && p.y() > 0.25 && p.y() < 0.35;
  });
  const CostField field(map, CostMapConfig{});
  TrajectoryOptimizer dut(TrajectoryOptimizerConfig{});
  TrajectoryRequest request = StraightRequest();
  request.guide_W = {{0, 0}, {10, 0}};
  const OptimizedTrajectory out = dut.Optimize(field, request);
  ASSERT_NE(out.status, OptimizationStatus::kInfeasible) << out.diagnostics.worst_constraint;
  EXPECT_LT(out.diagnostics.clearance_m, 0.0);
  EXPECT_GE(out.diagnostics.min_clearance_m,
            out.diagnostics.clearance_m - TrajectoryOptimizerConfig{}.violation_tolerance * 0.1);
  EXPECT_LE((out.trajectory.points().back().position_W - request.goal_W).norm(),
            10.0 * TrajectoryOptimizerConfig{}.terminal_tolerance_m);
}

TEST(TrajectoryOptimizerTest, AGoalInsideAWallIsReportedInfeasible) {
  common::GridLayers map = FlatMap();
  Paint(&map, 1.0f, [](const Eigen::Vector2d& p) { return p.x() >= 8; });
  const CostField field(map, CostMapConfig{});
  TrajectoryOptimizer dut(TrajectoryOptimizerConfig{});
  const OptimizedTrajectory out = dut.Optimize(field, StraightRequest());
  EXPECT_EQ(out.status, OptimizationStatus::kInfeasible);
  EXPECT_FALSE(out.trajectory.empty());
}

// A robot at rest to within rounding at its goal (a substitute goal in its own cell): the request
// of `probes/big_building.yaml` at seed 3, 292 s into the run, its y moved onto this map, which
// ended the run as an internal error. Nothing holds the pieces' durations up, and they shrink to
// 1e-17 s, below the resolution of the start time. The trajectory keeps the samples whose time
// advances: a hold at the start.
TEST(TrajectoryOptimizerTest, AStartAtRestAtItsGoalIsAHoldAtTheStart) {
  const CostField field(FlatMap(), CostMapConfig{});
  TrajectoryOptimizer dut(TrajectoryOptimizerConfig{});
  for (const double t_s : {2.0, 150.0, 292.35000000066782, 3600.0}) {
    TrajectoryRequest request;
    request.start.t_s = t_s;
    request.start.position_W = Eigen::Vector2d(1.790783, 1.976382);
    request.start.yaw = 0.021146;
    request.start.v = 3.85186e-34;
    request.start.acceleration = 8.27181e-25;
    request.goal_W = request.start.position_W;
    request.guide_W = {request.start.position_W};
    const OptimizedTrajectory out = dut.Optimize(field, request);
    ASSERT_FALSE(out.trajectory.empty()) << t_s;
    EXPECT_EQ(out.trajectory.start_time(), t_s);
    EXPECT_NE(out.status, OptimizationStatus::kInfeasible) << t_s;
    EXPECT_LE(ExtremesOf(out.trajectory).v, TrajectoryOptimizerConfig{}.limits.max_speed_m_s);
    for (const common::TrajectoryPoint& p : out.trajectory.points()) {
      EXPECT_LE((p.position_W - request.goal_W).norm(),
                TrajectoryOptimizerConfig{}.terminal_tolerance_m)
          << t_s;
    }
  }
}

TEST(TrajectoryOptimizerTest, RejectsAnInvalidConfigNamingTheKey) {
  TrajectoryOptimizerConfig config;
  config.limits.max_speed_m_s = 3.5;
  try {
    TrajectoryOptimizer dut(config);
    FAIL() << "no error";
  } catch (const common::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("max_speed: ", 0), 0u);
    EXPECT_NE(std::string(e.what()).find("3.5"), std::string::npos);
  }
  config = TrajectoryOptimizerConfig{};
  config.samples_per_piece = 7;
  EXPECT_THROW(TrajectoryOptimizer{config}, common::InputError);
}

}  // namespace
}  // namespace trav::planner
