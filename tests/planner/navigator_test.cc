// The navigator on its own (no simulator): synthetic maps and states.
#include "planner/navigation/navigator.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "tests/planner/planner_test_util.h"

namespace trav::planner {
namespace {

// 20 x 10 m at 0.2 m, cost 0.1 everywhere.
common::GridLayers OpenMap() {
  common::GridLayers map(
      common::GridGeometry::Centered(Eigen::Vector2d(5, 0), Eigen::Vector2d(20, 10), 0.2),
      {"traversability"});
  map.Layer("traversability").setConstant(0.1f);
  return map;
}

// Makes lethal the cells of `map` whose centres satisfy inside(centre).
template <typename Inside>
void PaintLethal(common::GridLayers* map, Inside inside) {
  const common::GridGeometry& g = map->geometry();
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      if (inside(g.CellCenter(ix, iy))) map->Layer("traversability")(ix, iy) = 1.0f;
    }
  }
}

common::RobotState At(double t_s, double x) {
  common::RobotState state;
  state.time_s = t_s;
  state.X_WB.translation() = Eigen::Vector3d(x, 0, 0.1);
  return state;
}

planner::Navigator MakeNavigator(const controller::MpcConfig& mpc = {}) {
  return planner::Navigator(planner::NavigationSettings{}, planner::NavigationPlannerConfig{}, mpc,
                            Eigen::Vector2d(8, 0));
}

// The default MPC with reverse limit `min_speed_m_s` [m/s].
controller::MpcConfig ReversingAtMost(double min_speed_m_s) {
  controller::MpcConfig mpc;
  mpc.min_speed_m_s = min_speed_m_s;
  return mpc;
}

TEST(NavigatorTest, WaitsForAMapThenPlansAndDrives) {
  planner::Navigator dut = MakeNavigator();
  const planner::NavigatorTick waiting = dut.Update(At(0.0, 0.0), nullptr, false, {});
  EXPECT_EQ(waiting.command.v, 0.0);
  EXPECT_EQ(waiting.replan, planner::ReplanReason::kNone);
  EXPECT_FALSE(waiting.solved);
  EXPECT_EQ(dut.statistics().plans, 0);
  EXPECT_TRUE(dut.trajectory().empty());
  const common::GridLayers map = OpenMap();
  common::Twist2 command;
  std::vector<planner::ReplanReason> replans;
  int solves = 0;
  for (int k = 0; k < 25; ++k) {
    const planner::NavigatorTick tick = dut.Update(At(0.02 * k, 0.0), &map, k == 0, {});
    command = tick.command;
    if (tick.replan != planner::ReplanReason::kNone) replans.push_back(tick.replan);
    solves += tick.solved;
  }
  // the tick says what was done: the first plan, then the periodic ones; an MPC solve each tick
  // at the default 50 Hz control rate
  EXPECT_EQ(replans, (std::vector<planner::ReplanReason>{planner::ReplanReason::kFirst,
                                                         planner::ReplanReason::kPeriodic,
                                                         planner::ReplanReason::kPeriodic}));
  EXPECT_EQ(solves, 25);
  EXPECT_EQ(dut.statistics().plans, 3);  // at 5 Hz: t = 0, 0.2 and 0.4 s
  EXPECT_EQ(dut.statistics().replans_on_events, 0);
  EXPECT_GT(command.v, 0.0);  // accelerating along the plan toward the goal
  EXPECT_NEAR(dut.trajectory().points().back().position_W.x(), 8.0, 0.05);
  EXPECT_EQ(dut.statistics().last_status, "planned");
}

TEST(NavigatorTest, LethalCellsAheadReplanAtOnceAndAMoverOnThePlanStopsTheRobot) {
  planner::Navigator dut = MakeNavigator();
  common::GridLayers map = OpenMap();
  dut.Update(At(0.0, 0.0), &map, true, {});
  ASSERT_EQ(dut.statistics().plans, 1);
  // a wall appears across the plan, with a way round at y > 2
  PaintLethal(&map,
              [](const Eigen::Vector2d& p) { return std::abs(p.x() - 4.0) < 0.15 && p.y() < 2.0; });
  dut.Update(At(0.06, 0.0), &map, true, {});  // inside the 0.1 s event blackout: deferred
  EXPECT_EQ(dut.statistics().plans, 1);
  // the pending map check replans now
  EXPECT_EQ(dut.Update(At(0.12, 0.0), &map, false, {}).replan,
            planner::ReplanReason::kNewLethalCells);
  EXPECT_EQ(dut.statistics().plans, 2);
  EXPECT_EQ(dut.statistics().replans_on_events, 1);
  double highest_y = -1.0;
  for (const common::TrajectoryPoint& p : dut.trajectory().points()) {
    if (std::abs(p.position_W.x() - 4.0) < 0.3) highest_y = std::max(highest_y, p.position_W.y());
  }
  EXPECT_GT(highest_y, 2.0);
  // a mover standing on the plan 0.5 s ahead: brake
  const common::TrajectoryPoint ahead = dut.trajectory().Sample(0.64);
  const planner::MovingObstacle mover{ahead.position_W, Eigen::Vector2d::Zero(), 0.3, 0.16};
  const planner::NavigatorTick stop = dut.Update(At(0.16, 0.0), &map, false, {mover});
  EXPECT_TRUE(stop.safety_stop);
  EXPECT_EQ(stop.command.v, 0.0);
  EXPECT_EQ(stop.command.omega, 0.0);
  EXPECT_EQ(dut.statistics().safety_stops, 1);
  EXPECT_EQ(dut.statistics().give_ways, 0);  // it stands still: no mover closes in
}

// A walker 1.5 m ahead of the robot at the origin at 0.02 s, coming straight at it at 1 m/s.
const planner::MovingObstacle kWalkerAhead{Eigen::Vector2d(1.5, 0.0), Eigen::Vector2d(-1.0, 0.0),
                                           0.3, 0.02};

// Plans on `map` from the origin at 0 s, then meets kWalkerAhead: the tick at 0.02 s.
planner::NavigatorTick MeetTheWalkerAhead(planner::Navigator* dut, const common::GridLayers& map) {
  dut->Update(At(0.0, 0.0), &map, true, {});
  return dut->Update(At(0.02, 0.0), &map, false, {kWalkerAhead});
}

TEST(NavigatorTest, AStoppedRobotBacksAwayFromAMoverComingAtIt) {
  planner::Navigator dut = MakeNavigator();
  const common::GridLayers map = OpenMap();
  // the plan ahead is unsafe, the robot stops, and since standing still it would be hit within a
  // second, it backs away
  const planner::NavigatorTick tick = MeetTheWalkerAhead(&dut, map);
  EXPECT_TRUE(tick.safety_stop);
  EXPECT_EQ(dut.statistics().give_ways, 1);
  EXPECT_LT(tick.command.v, 0.0);
  // the drive is straight back, its longest (1.6 m), at the walker's pace: the walker does not
  // close in while it lasts (at the 0.6 m/s of before, it closed 0.4 m every second)
  const common::Trajectory& drive = dut.trajectory();
  EXPECT_NEAR(drive.points().back().position_W.x(), -1.6, 1e-9);
  EXPECT_NEAR(drive.points().back().position_W.y(), 0.0, 1e-9);
  EXPECT_NEAR(drive.Sample(0.5).v, -1.0, 1e-12);
  for (const common::TrajectoryPoint& p : drive.points()) {
    EXPECT_GE((kWalkerAhead.PositionAt(p.t_s) - p.position_W).norm(), 1.5 - 1e-9) << p.t_s;
  }
  // followed to its end without replanning
  EXPECT_EQ(dut.Update(At(0.5, -0.2), &map, false, {kWalkerAhead}).replan,
            planner::ReplanReason::kNone);
  EXPECT_EQ(dut.statistics().plans, 1);
}

TEST(FreeDriveSpeedsTest, AreAWalkersPaceAndTheBackOffsWithinTheTrackersLimits) {
  const auto speeds = [](const controller::MpcConfig& mpc, double planner_max_speed_m_s) {
    planner::NavigationPlannerConfig planner;
    planner.optimizer.limits.max_speed_m_s = planner_max_speed_m_s;
    const planner::FreeDriveSpeeds s =
        planner::FreeDriveSpeedsFor(planner::PlanTrackingConfig(mpc, planner));
    return std::vector<double>{s.give_way_forward_m_s, s.give_way_backward_m_s, s.back_off_m_s};
  };
  // the defaults (MPC -1..1.5 m/s, planner 1.5 m/s): a walker's pace both ways, backing off slower
  EXPECT_EQ(speeds({}, 1.5), (std::vector<double>{1.0, 1.0, 0.6}));
  // a slower reverse limit caps the backward drives
  EXPECT_EQ(speeds(ReversingAtMost(-0.5), 1.5), (std::vector<double>{1.0, 0.5, 0.5}));
  // no reverse: no backward drive
  EXPECT_EQ(speeds(ReversingAtMost(0.0), 1.5), (std::vector<double>{1.0, 0.0, 0.0}));
  // the planner's speed limit caps the tracker both ways
  EXPECT_EQ(speeds({}, 0.8), (std::vector<double>{0.8, 0.8, 0.6}));
}

TEST(NavigatorTest, AStoppedRobotBacksAwayNoFasterThanTheTrackerMayReverse) {
  planner::Navigator dut = MakeNavigator(ReversingAtMost(-0.5));
  const common::GridLayers map = OpenMap();
  MeetTheWalkerAhead(&dut, map);
  ASSERT_EQ(dut.statistics().give_ways, 1);
  // straight back, at the reverse limit
  const common::Trajectory& drive = dut.trajectory();
  EXPECT_LT(drive.points().back().position_W.x(), -0.3);
  EXPECT_NEAR(drive.points().back().position_W.y(), 0.0, 1e-9);
  EXPECT_NEAR(drive.Sample(0.5).v, -0.5, 1e-12);
  for (const common::TrajectoryPoint& p : drive.points()) EXPECT_GE(p.v, -0.5 - 1e-12) << p.t_s;
}

TEST(NavigatorTest, AStoppedRobotThatMayNotReverseGivesWayForward) {
  planner::Navigator dut = MakeNavigator(ReversingAtMost(0.0));
  const common::GridLayers map = OpenMap();
  MeetTheWalkerAhead(&dut, map);
  ASSERT_EQ(dut.statistics().give_ways, 1);
  // a step aside, driven forward after a turn in place
  const common::Trajectory& drive = dut.trajectory();
  for (const common::TrajectoryPoint& p : drive.points()) EXPECT_GE(p.v, 0.0) << p.t_s;
  EXPECT_GT(std::abs(drive.points().back().position_W.y()), 0.3);
}

// The robot where `drive` puts it at t_s, facing along +x.
common::RobotState OnDriveAt(const common::Trajectory& drive, double t_s) {
  common::RobotState state = At(t_s, drive.Sample(t_s).position_W.x());
  state.X_WB.translation().y() = drive.Sample(t_s).position_W.y();
  return state;
}

TEST(NavigatorTest, AGiveWayDriveThatTheMapNowBlocksIsChosenAgain) {
  planner::Navigator dut = MakeNavigator();
  common::GridLayers map = OpenMap();
  MeetTheWalkerAhead(&dut, map);
  ASSERT_EQ(dut.statistics().give_ways, 1);
  const common::Trajectory back = dut.trajectory();
  // a map update shows an obstacle on the drive, 0.9 m behind the robot's base (a walker standing
  // there, which no track reports): the drive is not followed into it
  PaintLethal(&map, [](const Eigen::Vector2d& p) {
    return std::abs(p.x() + 1.0) < 0.15 && std::abs(p.y()) < 0.3;
  });
  const planner::NavigatorTick tick = dut.Update(OnDriveAt(back, 0.3), &map, true, {kWalkerAhead});
  // a new drive, clear of the obstacle (the walker ahead still closes in, so the robot does not
  // just stop)
  EXPECT_FALSE(tick.safety_stop);
  EXPECT_EQ(dut.statistics().give_ways, 2);
  for (const common::TrajectoryPoint& p : dut.trajectory().points()) {
    EXPECT_FALSE(std::abs(p.position_W.x() + 1.0) < 0.6 && std::abs(p.position_W.y()) < 0.6)
        << p.position_W.transpose();
  }
}

TEST(NavigatorTest, AGiveWayDriveThatTheMapNowBlocksIsStoppedWhereNoOtherGainsRoom) {
  planner::Navigator dut = MakeNavigator();
  common::GridLayers map = OpenMap();
  // a corridor 1.2 m wide along x (walls' cells at |y| >= 0.7 m): no room to turn in place
  PaintLethal(&map, [](const Eigen::Vector2d& p) {
    return std::abs(p.y()) > 0.6 && std::abs(p.y()) < 1.2;
  });
  MeetTheWalkerAhead(&dut, map);
  ASSERT_EQ(dut.statistics().give_ways, 1);
  const common::Trajectory back = dut.trajectory();
  ASSERT_LT(back.points().back().position_W.x(), -0.3);
  ASSERT_NEAR(back.points().back().position_W.y(), 0.0, 1e-9);
  // the map now closes the corridor 0.9 m behind the base: back is blocked, forward meets the
  // walker, and no turn fits; the robot stops and will replan
  PaintLethal(&map, [](const Eigen::Vector2d& p) { return std::abs(p.x() + 1.0) < 0.15; });
  const planner::NavigatorTick tick = dut.Update(OnDriveAt(back, 0.3), &map, true, {kWalkerAhead});
  EXPECT_TRUE(tick.safety_stop);
  EXPECT_EQ(tick.command.v, 0.0);
  EXPECT_EQ(tick.command.omega, 0.0);
  EXPECT_EQ(dut.statistics().give_ways, 1);
}

TEST(NavigatorTest, AStoppedRobotWithAWallBehindStepsAsideFromAMoverComingAtIt) {
  planner::Navigator dut = MakeNavigator();
  common::GridLayers map = OpenMap();
  // a wall 0.7 m behind the base (0.4 m behind the robot's rear): no room to back away
  PaintLethal(&map, [](const Eigen::Vector2d& p) { return p.x() < -0.7 && p.x() > -1.1; });
  dut.Update(At(0.0, 0.0), &map, true, {});
  // a walker 2.5 m ahead coming straight at the robot at 1 m/s: straight back is blocked and
  // straight forward meets it, so the robot turns in place and drives out of its line
  const planner::MovingObstacle walker{Eigen::Vector2d(2.5, 0.0), Eigen::Vector2d(-1.0, 0.0), 0.3,
                                       0.02};
  const planner::NavigatorTick tick = dut.Update(At(0.02, 0.0), &map, false, {walker});
  EXPECT_TRUE(tick.safety_stop);
  EXPECT_EQ(dut.statistics().give_ways, 1);
  const Eigen::Vector2d end_W = dut.trajectory().points().back().position_W;
  EXPECT_GT(std::abs(end_W.y()), 0.5);
  EXPECT_GT(end_W.x(), -0.3);
}

// A dead end 1 m wide (walls' cells centred at |y| >= 0.6 m) closed at x = 1.3, too narrow to turn
// the robot in (its circumscribed disc plus the clearance is 1.05 m across), with the robot at
// x = 0.5 facing its end; the goal behind it. One optimiser iteration,
// so that every plan falls back: on the pose search's way backward.
struct DeadEnd {
  DeadEnd() {
    PaintLethal(&map, [](const Eigen::Vector2d& p) {
      return p.x() > -3.0 && p.x() < 1.6 && std::abs(p.y()) < 0.9 &&
             (std::abs(p.y()) > 0.5 || p.x() > 1.2);
    });
    config.optimizer.max_iterations = 1;
    config.optimizer.terminal_tolerance_m = 1e-6;
  }

  // The robot exactly on `way` at t_s.
  static common::RobotState On(const common::Trajectory& way, double t_s) {
    const common::TrajectoryPoint p = way.Sample(t_s);
    common::RobotState state;
    state.time_s = t_s;
    state.X_WB.translation() = Eigen::Vector3d(p.position_W.x(), p.position_W.y(), 0.1);
    state.X_WB.linear() = Eigen::AngleAxisd(p.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    state.v_WB_B.x() = p.v;
    return state;
  }

  common::GridLayers map{OpenMap()};
  planner::NavigationPlannerConfig config;
};

TEST(NavigatorTest, AWayOutOfTheNarrowsIsFollowedWithoutPeriodicReplansOverItsFirstMetre) {
  DeadEnd world;
  planner::Navigator dut(planner::NavigationSettings{}, world.config, controller::MpcConfig{},
                         Eigen::Vector2d(-6, 0));
  dut.Update(At(0.0, 0.5), &world.map, true, {});
  ASSERT_EQ(dut.statistics().plans, 1);
  ASSERT_EQ(dut.statistics().last_status.substr(0, 7), "planned");
  ASSERT_NE(dut.statistics().last_status.find("pose-search"), std::string::npos);
  // backward along the dead end, narrow all the way: no periodic replan over the first metre of
  // the way (3.33 s at 0.3 m/s), then one; the way counts as a valid plan meanwhile
  const common::Trajectory way = dut.trajectory();
  std::optional<double> first_replan_s;
  for (int k = 1; k * 0.02 < way.end_time() && !first_replan_s; ++k) {
    const common::RobotState state = DeadEnd::On(way, 0.02 * k);
    EXPECT_LE(dut.time_without_plan_s(state.time_s), 0.02) << state.time_s;  // a tick at most
    const planner::NavigatorTick tick = dut.Update(state, &world.map, false, {});
    if (tick.replan != planner::ReplanReason::kNone) {
      EXPECT_EQ(tick.replan, planner::ReplanReason::kPeriodic);
      first_replan_s = state.time_s;
      EXPECT_NEAR(state.X_WB.translation().x(), 0.5 - 1.0, 0.02);
    }
  }
  ASSERT_TRUE(first_replan_s.has_value());
  EXPECT_NEAR(*first_replan_s, 1.0 / 0.3, 0.05);
}

TEST(NavigatorTest, GivingWayOnAFollowedWayEndsItsCommitment) {
  DeadEnd world;
  planner::Navigator dut(planner::NavigationSettings{}, world.config, controller::MpcConfig{},
                         Eigen::Vector2d(-6, 0));
  dut.Update(At(0.0, 0.5), &world.map, true, {});
  const common::Trajectory way = dut.trajectory();
  const common::RobotState on_way = DeadEnd::On(way, 1.0);
  ASSERT_EQ(dut.Update(on_way, &world.map, false, {}).replan, planner::ReplanReason::kNone);
  // a walker coming up the dead end at 0.4 m/s into the robot backing out of it: the robot stops
  // and drives back into the dead end, out of its way, and the way it was committed to is given
  // up there: from then on the time without a plan runs
  const planner::MovingObstacle walker{
      on_way.X_WB.translation().head<2>() - Eigen::Vector2d(1.3, 0.0), Eigen::Vector2d(0.4, 0.0),
      0.3, 0.02};
  const double t_s = on_way.time_s + 0.02;
  common::RobotState stopped = on_way;
  stopped.time_s = t_s;
  const planner::NavigatorTick tick = dut.Update(stopped, &world.map, false, {walker});
  ASSERT_TRUE(tick.safety_stop);
  ASSERT_EQ(dut.statistics().give_ways, 1);
  EXPECT_GT(dut.trajectory().points().back().position_W.x(), on_way.X_WB.translation().x() + 0.3);
  EXPECT_DOUBLE_EQ(dut.time_without_plan_s(t_s), 0.0);
  EXPECT_DOUBLE_EQ(dut.time_without_plan_s(t_s + 0.5), 0.5);
}

TEST(NavigatorTest, AFollowedWayIsReplannedWhenTheMapClosesInOnItsFootprint) {
  DeadEnd world;
  planner::Navigator dut(planner::NavigationSettings{}, world.config, controller::MpcConfig{},
                         Eigen::Vector2d(-6, 0));
  dut.Update(At(0.0, 0.5), &world.map, true, {});
  const common::Trajectory way = dut.trajectory();
  EXPECT_EQ(dut.Update(DeadEnd::On(way, 0.1), &world.map, true, {}).replan,
            planner::ReplanReason::kNone);
  // a cell at the side of the way 1 m behind the robot turns lethal (y from 0.3 to 0.5 m): the
  // base's path stays clear of it, the footprint would not
  PaintLethal(&world.map, [](const Eigen::Vector2d& p) {
    return (p - Eigen::Vector2d(-0.6, 0.4)).norm() < 0.1;
  });
  EXPECT_EQ(dut.Update(DeadEnd::On(way, 0.2), &world.map, true, {}).replan,
            planner::ReplanReason::kNewLethalCells);
}

// Ticks a robot that rocks in place at the origin (1 mm back and forth at 0.05 m/s, as against a
// curb it cannot climb) every 0.02 s from 0 s on `map`, until the navigator first backs off or for
// 3 s: when and where it backed off (nullopt if it never did) and every replan reason.
struct Stall {
  std::optional<double> back_off_s;
  double x_m{0.0};
  std::vector<planner::ReplanReason> replans;
};
Stall StallAtTheOrigin(planner::Navigator* dut, const common::GridLayers& map) {
  Stall stall;
  for (int k = 0; k <= 150 && !stall.back_off_s; ++k) {
    common::RobotState state = At(0.02 * k, 0.001 * (k % 2));
    state.v_WB_B.x() = k % 2 == 0 ? -0.05 : 0.05;  // rocking: never slower than 0.03 m/s
    const planner::NavigatorTick tick = dut->Update(state, &map, k == 0, {});
    if (tick.replan != planner::ReplanReason::kNone) stall.replans.push_back(tick.replan);
    if (dut->statistics().back_offs > 0) {
      stall.back_off_s = state.time_s;
      stall.x_m = state.X_WB.translation().x();
    }
  }
  return stall;
}

TEST(NavigatorTest, AStalledRobotBacksOffStraightForARunUpThenReplans) {
  planner::Navigator dut = MakeNavigator();
  const common::GridLayers map = OpenMap();
  const Stall stall = StallAtTheOrigin(&dut, map);
  // the plan asks for 0.3 m/s from about 0.2 s (1.5 m/s^2); a second later, still within 3 mm of
  // the origin, the robot has stalled: no replan for it, a drive straight back by 1.2 m instead
  ASSERT_TRUE(stall.back_off_s.has_value());
  EXPECT_GT(*stall.back_off_s, 1.1);
  EXPECT_LT(*stall.back_off_s, 1.5);
  EXPECT_EQ(std::count(stall.replans.begin(), stall.replans.end(), planner::ReplanReason::kStalled),
            0);
  EXPECT_EQ(dut.statistics().back_offs, 1);
  EXPECT_EQ(dut.statistics().give_ways, 0);
  const common::Trajectory drive = dut.trajectory();
  EXPECT_NEAR(drive.points().back().position_W.x(), stall.x_m - 1.2, 1e-9);
  EXPECT_NEAR(drive.points().back().position_W.y(), 0.0, 1e-9);
  EXPECT_NEAR(drive.end_time() - *stall.back_off_s, 1.2 / 0.6, 0.02);  // at the back-off speed
  // followed backward to its end without replanning (the command brakes from the stalled
  // forward one, then reverses), then the robot replans from where it is
  double slowest_command = 0.0;
  for (double t = *stall.back_off_s + 0.02; t < drive.end_time(); t += 0.02) {
    const planner::NavigatorTick backing = dut.Update(OnDriveAt(drive, t), &map, false, {});
    EXPECT_EQ(backing.replan, planner::ReplanReason::kNone);
    slowest_command = std::min(slowest_command, backing.command.v);
  }
  EXPECT_LT(slowest_command, -0.3);
  const planner::NavigatorTick after =
      dut.Update(OnDriveAt(drive, drive.end_time() + 0.02), &map, false, {});
  EXPECT_NE(after.replan, planner::ReplanReason::kNone);
  EXPECT_NEAR(dut.trajectory().points().back().position_W.x(), 8.0, 0.05);
}

TEST(NavigatorTest, AStalledRobotBacksOffOnlyAsFarAsTheMapLeavesItRoom) {
  planner::Navigator dut = MakeNavigator();
  common::GridLayers map = OpenMap();
  // a wall 1.4 m behind the origin: the 1.2 m drive would put the robot's back (0.31 m behind
  // the base) into it, 0.8 m keeps it 0.29 m clear
  PaintLethal(&map, [](const Eigen::Vector2d& p) { return p.x() < -1.4; });
  const Stall stall = StallAtTheOrigin(&dut, map);
  ASSERT_TRUE(stall.back_off_s.has_value());
  EXPECT_NEAR(dut.trajectory().points().back().position_W.x(), stall.x_m - 0.8, 1e-9);
}

TEST(NavigatorTest, AStalledRobotWithNoRoomBehindReplansWhereItIs) {
  planner::Navigator dut = MakeNavigator();
  common::GridLayers map = OpenMap();
  // the wall right behind the robot's back: any drive backward comes closer to it
  PaintLethal(&map, [](const Eigen::Vector2d& p) { return p.x() < -0.4; });
  const Stall stall = StallAtTheOrigin(&dut, map);
  EXPECT_FALSE(stall.back_off_s.has_value());
  EXPECT_EQ(dut.statistics().back_offs, 0);
  // stalled after about 1.2 s, then again a second after each stall replan
  EXPECT_EQ(std::count(stall.replans.begin(), stall.replans.end(), planner::ReplanReason::kStalled),
            2);
}

// OpenMap with stairs up along the way from x = 1 m, a step of `step_height_m` every 0.4 m, in
// the roughness layer as the mappers read it: 0.14 m steps reach the base (within the
// footprint's circumscribed radius, 0.42 m) from x = 0.5 m on.
common::GridLayers StairsMap(double step_height_m) {
  common::GridLayers map = OpenMap();
  test_util::PaintRoughness(&map, [step_height_m](const Eigen::Vector2d& p) {
    return p.x() > 1.0 ? step_height_m * std::ceil((p.x() - 1.0) / 0.4) : 0.0;
  });
  return map;
}

// A tracker that commands what the test sets, whatever its reference.
class ScriptedTracker : public controller::TrajectoryTracker {
 public:
  explicit ScriptedTracker(const common::Twist2* command) : command_(command) {}
  void SetReference(common::Trajectory reference) override { reference_ = std::move(reference); }
  common::Twist2 Command(const common::RobotState&) override { return *command_; }
  bool SolveDue(double) const override { return true; }
  controller::TrackingMetrics Metrics() const override { return {}; }
  const common::Trajectory& reference() const override { return reference_; }
  int solves() const override { return 0; }
  const Eigen::Matrix3Xd& predicted_states_W() const override { return predicted_W_; }

 private:
  const common::Twist2* command_;
  common::Trajectory reference_;
  Eigen::Matrix3Xd predicted_W_;
};

// A navigator toward (8, 0) whose tracker commands *command, tracking with `mpc`'s limits.
planner::Navigator ScriptedNavigator(const common::Twist2* command,
                                     const planner::NavigationSettings& settings = {},
                                     const controller::MpcConfig& mpc = {}) {
  return planner::Navigator(settings, planner::NavigationPlannerConfig{}, mpc,
                            Eigen::Vector2d(8, 0), planner::AStarSearch,
                            std::make_unique<ScriptedTracker>(command));
}

// The robot at (x_m, 0) at t_s heading +x with its nose up by `nose_up_deg` (negative: down).
common::RobotState NoseUp(double t_s, double x_m, double nose_up_deg) {
  common::RobotState state = At(t_s, x_m);
  state.X_WB.linear() =
      Eigen::AngleAxisd(-nose_up_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return state;
}

// The tick of `dut` on `map` with the robot's nose up by 15 deg at x = 1 m (over the first of
// StairsMap's steps), after a first tick level at the origin.
planner::NavigatorTick NoseUpOverTheFirstStep(planner::Navigator* dut,
                                              const common::GridLayers& map) {
  dut->Update(NoseUp(0.0, 0.0, 0.0), &map, true, {});
  return dut->Update(NoseUp(0.02, 1.0, 15.0), &map, false, {});
}

TEST(NavigatorTest, ClimbsAStepStraightAtTheClimbSpeedWhileItsNoseIsUpOverIt) {
  const common::GridLayers map = StairsMap(0.14);
  common::Twist2 command{0.8, 0.4};  // the tracker's: on and turning
  planner::Navigator dut = ScriptedNavigator(&command);
  double t = 0.0;
  auto tick = [&](double x_m, double nose_up_deg) {
    const planner::NavigatorTick done = dut.Update(NoseUp(t, x_m, nose_up_deg), &map, t == 0.0, {});
    t += 0.02;
    return done;
  };
  auto holds = [](const planner::NavigatorTick& done) {
    return done.climbing && done.command.v == 1.1 && done.command.omega == 0.0;
  };
  // level, or nose up short of the stairs (a slope): the tracker's command
  for (const auto& [x_m, nose_up_deg] :
       std::vector<std::pair<double, double>>{{0.0, 0.0}, {0.2, 15.0}, {1.0, 0.0}}) {
    const planner::NavigatorTick other = tick(x_m, nose_up_deg);
    EXPECT_FALSE(other.climbing) << x_m << " " << nose_up_deg;
    EXPECT_EQ(other.command.v, 0.8);
    EXPECT_EQ(other.command.omega, 0.4);
  }
  // nose up by 15 deg over the first step: a climb, straight at the climb speed, held whatever
  // the pitch (it falls as the rear wheels climb) and while the tracker slows (to 0.1 m/s),
  // ended when the tracker reverses (a stall's back-off)
  EXPECT_TRUE(holds(tick(1.0, 15.0)));
  EXPECT_TRUE(holds(tick(1.0, 0.0)));
  command = {0.1, 0.4};
  EXPECT_TRUE(holds(tick(1.0, -5.0)));
  command = {-0.2, 0.0};
  EXPECT_FALSE(tick(1.0, 15.0).climbing);
  EXPECT_EQ(dut.statistics().step_climbs, 1);
  // a climb starts only when the tracker means to drive on (0.3 m/s or more) and the nose is up
  // by the climb pitch (10 deg)
  command = {0.2, 0.4};
  EXPECT_FALSE(tick(1.0, 15.0).climbing);
  command = {0.8, 0.4};
  EXPECT_FALSE(tick(1.0, 9.0).climbing);
  EXPECT_TRUE(holds(tick(1.05, 15.0)));
  EXPECT_EQ(dut.statistics().step_climbs, 2);
  // held until the robot has driven the footprint's length (0.626 m) from where the climb began,
  // then not again while the nose stays up, though it is still on the stairs
  for (double x = 1.1; x < 1.05 + 0.62; x += 0.05) EXPECT_TRUE(holds(tick(x, 2.0))) << x;
  EXPECT_FALSE(tick(1.7, 15.0).climbing);
  EXPECT_FALSE(tick(2.5, 15.0).climbing);
  EXPECT_EQ(dut.statistics().step_climbs, 2);
  // the nose down, then up: a new climb
  EXPECT_FALSE(tick(2.5, 0.0).climbing);
  EXPECT_TRUE(holds(tick(2.5, 15.0)));
  EXPECT_EQ(dut.statistics().step_climbs, 3);
}

TEST(NavigatorTest, ClimbsOnlyOverAStepOfTheClimbStep) {
  // 0.06 m stairs (their edges read 0.03 m of roughness) are below `climb_step` (0.08 m): no
  // climb on them, unless the climb step is lower
  const common::GridLayers map = StairsMap(0.06);
  const common::Twist2 command{0.8, 0.4};
  planner::NavigationSettings low;
  low.climb_step_m = 0.05;
  for (const bool lower : {false, true}) {
    planner::Navigator dut =
        ScriptedNavigator(&command, lower ? low : planner::NavigationSettings{});
    EXPECT_EQ(NoseUpOverTheFirstStep(&dut, map).climbing, lower);
  }
}

TEST(NavigatorTest, HoldsNoClimbTowardAnObstacle) {
  // a block on the stairs 0.5 m ahead of the base at x = 1 m: driving straight for the
  // footprint's length would put the robot's front into it (the plan goes round it)
  common::GridLayers map = StairsMap(0.14);
  PaintLethal(&map, [](const Eigen::Vector2d& p) {
    return p.x() > 1.5 && p.x() < 1.9 && std::abs(p.y()) < 0.6;
  });
  const common::Twist2 command{0.8, 0.4};
  planner::Navigator dut = ScriptedNavigator(&command);
  EXPECT_FALSE(NoseUpOverTheFirstStep(&dut, map).climbing);
  EXPECT_EQ(dut.statistics().step_climbs, 0);
}

TEST(NavigatorTest, ClimbsNoFasterThanTheTrackerMayDriveAndNotAtAllWithTheClimbSpeedZero) {
  const common::GridLayers map = StairsMap(0.14);
  const common::Twist2 command{0.8, 0.4};
  controller::MpcConfig slow;
  slow.max_speed_m_s = 0.7;
  planner::NavigationSettings off;
  off.climb_speed_m_s = 0.0;
  for (const bool hold : {true, false}) {
    planner::Navigator dut =
        ScriptedNavigator(&command, hold ? planner::NavigationSettings{} : off, slow);
    const planner::NavigatorTick climbing = NoseUpOverTheFirstStep(&dut, map);
    EXPECT_EQ(climbing.climbing, hold);
    EXPECT_EQ(climbing.command.v, hold ? 0.7 : 0.8);
    EXPECT_EQ(climbing.command.omega, hold ? 0.0 : 0.4);
  }
}

TEST(NavigatorTest, AStalledRobotThatMayNotReverseReplansWhereItIs) {
  planner::Navigator dut = MakeNavigator(ReversingAtMost(0.0));
  const Stall stall = StallAtTheOrigin(&dut, OpenMap());
  EXPECT_FALSE(stall.back_off_s.has_value());
  EXPECT_EQ(std::count(stall.replans.begin(), stall.replans.end(), planner::ReplanReason::kStalled),
            2);
}

}  // namespace
}  // namespace trav::planner
