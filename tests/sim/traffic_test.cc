#include "sim/actors/traffic.h"

#include <cmath>
#include <variant>

#include <gtest/gtest.h>

namespace trav::sim {
namespace {

const Eigen::Vector2d kStart(-10.0, 0.0);
const Eigen::Vector2d kGoal(10.0, 0.0);

TEST(TrafficTest, RandomWalkersStayInDiscsClearOfStartAndGoal) {
  sim::TrafficSettings traffic;
  traffic.count = 12;
  traffic.speed_m_s = 1.5;
  const std::vector<sim::MovingObstacle> movers = sim::SpawnTraffic(traffic, kStart, kGoal);
  ASSERT_EQ(movers.size(), 12u);
  for (std::size_t k = 0; k < movers.size(); ++k) {
    EXPECT_EQ(movers[k].name, "traffic_" + std::to_string(k));
    const auto* walk = std::get_if<sim::RandomWalkMotion>(&movers[k].motion);
    ASSERT_NE(walk, nullptr);
    EXPECT_EQ(walk->speed_m_s, 1.5);
    // the disc along the middle of the route, its edge 2 m plus a body radius from start and goal
    EXPECT_GE(walk->area_centre_W.x(), -6.0);
    EXPECT_LE(walk->area_centre_W.x(), 6.0);
    EXPECT_LE(std::abs(walk->area_centre_W.y()), 4.0);
    for (const Eigen::Vector2d& end : {kStart, kGoal}) {
      EXPECT_GE((walk->area_centre_W - end).norm(), 2.5 + 2.0 + movers[k].radius_m);
    }
    // wherever it walks, it stays clear of both
    sim::MoverTrack track(movers[k]);
    for (double t = 0.0; t < 60.0; t += 0.5) {
      const Eigen::Vector2d p = track.PlanarStateAt(t).p_W;
      EXPECT_GE((p - kStart).norm(), 2.0 + movers[k].radius_m);
      EXPECT_GE((p - kGoal).norm(), 2.0 + movers[k].radius_m);
    }
  }
}

TEST(TrafficTest, CrossersCrossTheRouteWhereARobotAtOneMetrePerSecondWouldBe) {
  sim::TrafficSettings traffic;
  traffic.count = 6;
  traffic.speed_m_s = 0.8;
  traffic.behaviour = sim::TrafficBehaviour::kCrossing;
  for (const sim::MovingObstacle& mover : sim::SpawnTraffic(traffic, kStart, kGoal)) {
    const auto* crossing = std::get_if<sim::ConstantVelocityMotion>(&mover.motion);
    ASSERT_NE(crossing, nullptr);
    EXPECT_NEAR(crossing->velocity_W.norm(), 0.8, 1e-12);
    EXPECT_NEAR(crossing->velocity_W.x(), 0.0, 1e-12);  // across the route along +x
    const double offset = std::abs(crossing->start_W.y());
    EXPECT_GE(offset, 6.0);
    EXPECT_LE(offset, 10.0);
    // on the route (y = 0) when the robot, leaving at t = 0 at 1 m/s, reaches its x
    const double at_route_s = crossing->start_time_s + offset / 0.8;
    EXPECT_NEAR(at_route_s, std::max(crossing->start_W.x() - kStart.x(), offset / 0.8), 1e-9);
  }
}

TEST(TrafficTest, CartsAndBoxesKeepTheirWholeFootprintClear) {
  sim::TrafficSettings traffic;
  traffic.count = 5;
  traffic.shape = sim::TrafficShape::kCart;
  traffic.behaviour = sim::TrafficBehaviour::kCrossing;
  for (const sim::MovingObstacle& mover : sim::SpawnTraffic(traffic, kStart, kGoal)) {
    EXPECT_EQ(mover.shape, sim::MoverShape::kBox);
    EXPECT_EQ(mover.box_half_extents_m, Eigen::Vector2d(0.5, 0.35));
    const Eigen::Vector2d p0 = sim::MoverTrack(mover).PlanarStateAt(0.0).p_W;
    EXPECT_GE((p0 - kStart).norm(), 2.0 + sim::MoverFootprintRadius(mover));
  }
  traffic.shape = sim::TrafficShape::kBox;
  EXPECT_EQ(sim::SpawnTraffic(traffic, kStart, kGoal)[0].half_height_m, 0.4);
}

TEST(TrafficTest, ReactiveWalkersGoBackAndForthAcrossTheRouteKeepingTheirDistance) {
  sim::TrafficSettings traffic;
  traffic.count = 3;
  traffic.behaviour = sim::TrafficBehaviour::kReactive;
  for (const sim::MovingObstacle& mover : sim::SpawnTraffic(traffic, kStart, kGoal)) {
    const auto& path = std::get<sim::WaypointMotion>(mover.motion);
    EXPECT_EQ(path.loop, sim::WaypointLoop::kPingPong);
    ASSERT_EQ(path.waypoints_W.size(), 2u);
    EXPECT_NEAR(std::abs(path.waypoints_W[0].y()), 6.0, 1e-9);
    EXPECT_NEAR(path.waypoints_W[0].y(), -path.waypoints_W[1].y(), 1e-9);
    EXPECT_EQ(mover.personal_distance_m, 0.8);
  }
}

TEST(TrafficTest, SameSeedSameMoversAndNoneWithoutACount) {
  sim::TrafficSettings traffic;
  traffic.count = 3;
  traffic.seed = 9;
  const auto a = sim::SpawnTraffic(traffic, kStart, kGoal);
  const auto b = sim::SpawnTraffic(traffic, kStart, kGoal);
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(std::get<sim::RandomWalkMotion>(a[k].motion).area_centre_W,
              std::get<sim::RandomWalkMotion>(b[k].motion).area_centre_W);
    EXPECT_EQ(std::get<sim::RandomWalkMotion>(a[k].motion).seed,
              std::get<sim::RandomWalkMotion>(b[k].motion).seed);
  }
  traffic.seed = 10;
  EXPECT_NE(std::get<sim::RandomWalkMotion>(sim::SpawnTraffic(traffic, kStart, kGoal)[0].motion)
                .area_centre_W,
            std::get<sim::RandomWalkMotion>(a[0].motion).area_centre_W);
  traffic.count = 0;
  EXPECT_TRUE(sim::SpawnTraffic(traffic, kStart, kGoal).empty());
}

TEST(TrafficTest, StreamsHeadOnAndOvertakingMoveAsSpecified) {
  sim::TrafficSettings traffic;
  traffic.count = 4;
  traffic.speed_m_s = 0.5;
  traffic.behaviour = sim::TrafficBehaviour::kFlow;
  const auto flow = sim::SpawnTraffic(traffic, kStart, kGoal);
  ASSERT_EQ(flow.size(), 4u);
  for (std::size_t k = 0; k < flow.size(); ++k) {
    sim::MoverTrack track(flow[k]);
    const auto& motion = std::get<sim::ConstantVelocityMotion>(flow[k].motion);
    EXPECT_DOUBLE_EQ(motion.start_time_s, 2.0 * static_cast<double>(k));  // one every 2 s
    EXPECT_NEAR(std::abs(motion.start_W.y()), 8.0, 1e-12);  // from alternate sides, 8 m away
    EXPECT_NEAR(motion.start_W.x(), 0.0, 0.5);              // across the middle of the route
    // on the route 8 m / 0.5 m/s = 16 s after it leaves
    EXPECT_NEAR(track.PlanarStateAt(motion.start_time_s + 16.0).p_W.y(), 0.0, 1e-9);
  }
  EXPECT_LT(std::get<sim::ConstantVelocityMotion>(flow[0].motion).start_W.y() *
                std::get<sim::ConstantVelocityMotion>(flow[1].motion).start_W.y(),
            0.0);  // alternate sides
  traffic.behaviour = sim::TrafficBehaviour::kHeadOn;
  for (const sim::MovingObstacle& mover : sim::SpawnTraffic(traffic, kStart, kGoal)) {
    sim::MoverTrack track(mover);
    const auto& motion = std::get<sim::ConstantVelocityMotion>(mover.motion);
    EXPECT_EQ(motion.velocity_W, Eigen::Vector2d(-0.5, 0.0));  // towards the start
    EXPECT_GE(motion.start_W.x(), 2.0 - 1e-9);                 // from the last 40 % of the route
    EXPECT_LE(std::abs(motion.start_W.y()), 1.0);
    const double t = motion.start_time_s + 4.0;
    EXPECT_NEAR(track.PlanarStateAt(t).p_W.x(), motion.start_W.x() - 2.0, 1e-9);
  }
  traffic.behaviour = sim::TrafficBehaviour::kOvertaking;
  for (const sim::MovingObstacle& mover : sim::SpawnTraffic(traffic, kStart, kGoal)) {
    const auto& motion = std::get<sim::ConstantVelocityMotion>(mover.motion);
    EXPECT_EQ(motion.velocity_W, Eigen::Vector2d(0.5, 0.0));  // towards the goal
    EXPECT_LE(motion.start_W.x(), 0.0 + 1e-9);                // from the first half
    EXPECT_EQ(motion.start_time_s, 0.0);
  }
}

}  // namespace
}  // namespace trav::sim
