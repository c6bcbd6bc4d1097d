#include "scenarios/traffic.h"

#include <cmath>
#include <variant>

#include <gtest/gtest.h>

#include "common/input_error.h"
#include "common/yaml_reader.h"
#include "scenarios/scenario.h"

namespace trav::scenarios {
namespace {

const Eigen::Vector2d kStart(-10.0, 0.0);
const Eigen::Vector2d kGoal(10.0, 0.0);

TEST(TrafficTest, RandomWalkersStayInDiscsClearOfStartAndGoal) {
  TrafficSettings traffic;
  traffic.count = 12;
  traffic.speed_m_s = 1.5;
  const std::vector<sim::MovingObstacle> movers = SpawnTraffic(traffic, kStart, kGoal);
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
  TrafficSettings traffic;
  traffic.count = 6;
  traffic.speed_m_s = 0.8;
  traffic.behaviour = TrafficBehaviour::kCrossing;
  for (const sim::MovingObstacle& mover : SpawnTraffic(traffic, kStart, kGoal)) {
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

TEST(TrafficTest, SameSeedSameMoversAndNoneWithoutACount) {
  TrafficSettings traffic;
  traffic.count = 3;
  traffic.seed = 9;
  const auto a = SpawnTraffic(traffic, kStart, kGoal);
  const auto b = SpawnTraffic(traffic, kStart, kGoal);
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(std::get<sim::RandomWalkMotion>(a[k].motion).area_centre_W,
              std::get<sim::RandomWalkMotion>(b[k].motion).area_centre_W);
    EXPECT_EQ(std::get<sim::RandomWalkMotion>(a[k].motion).seed,
              std::get<sim::RandomWalkMotion>(b[k].motion).seed);
  }
  traffic.seed = 10;
  EXPECT_NE(
      std::get<sim::RandomWalkMotion>(SpawnTraffic(traffic, kStart, kGoal)[0].motion).area_centre_W,
      std::get<sim::RandomWalkMotion>(a[0].motion).area_centre_W);
  traffic.count = 0;
  EXPECT_TRUE(SpawnTraffic(traffic, kStart, kGoal).empty());
}

TEST(TrafficTest, AScenarioAppendsItsTrafficAndItsResolvedFileRegeneratesIt) {
  const Scenario scenario = LoadScenario(common::YamlDocument::Parse(
      "robot: {start: [-10, 0, 0]}\ngoal: [10, 0]\n"
      "moving_obstacles: [{name: cart, motion: constant_velocity, velocity: [1, 0]}]\n"
      "traffic: {count: 4, speed: 1.2, behaviour: crossing, seed: 3}\n",
      "traffic.yaml"));
  ASSERT_EQ(scenario.movers.size(), 5u);
  EXPECT_EQ(scenario.movers[0].name, "cart");
  EXPECT_EQ(scenario.movers[4].name, "traffic_3");
  const Scenario replayed =
      LoadScenario(common::YamlDocument::Parse(ResolvedScenarioYaml(scenario), "resolved.yaml"));
  ASSERT_EQ(replayed.movers.size(), 5u);
  EXPECT_EQ(std::get<sim::ConstantVelocityMotion>(replayed.movers[4].motion).start_W,
            std::get<sim::ConstantVelocityMotion>(scenario.movers[4].motion).start_W);
  EXPECT_THROW(LoadScenario(common::YamlDocument::Parse("traffic: {speed: 5}\n", "bad.yaml")),
               common::InputError);
}

}  // namespace
}  // namespace trav::scenarios
