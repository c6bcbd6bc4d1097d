#include "scenarios/traffic.h"

#include <cmath>
#include <variant>

#include <gtest/gtest.h>

#include "common/input_error.h"
#include "common/yaml_reader.h"
#include "scenarios/scenario.h"
#include "scenarios/scenario_run.h"
#include "sim/terrain.h"
#include "sim/terrain_geometry.h"

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

TEST(TrafficTest, CartsAndBoxesKeepTheirWholeFootprintClear) {
  TrafficSettings traffic;
  traffic.count = 5;
  traffic.shape = TrafficShape::kCart;
  traffic.behaviour = TrafficBehaviour::kCrossing;
  for (const sim::MovingObstacle& mover : SpawnTraffic(traffic, kStart, kGoal)) {
    EXPECT_EQ(mover.shape, sim::MoverShape::kBox);
    EXPECT_EQ(mover.box_half_extents_m, Eigen::Vector2d(0.5, 0.35));
    const Eigen::Vector2d p0 = sim::MoverTrack(mover).PlanarStateAt(0.0).p_W;
    EXPECT_GE((p0 - kStart).norm(), 2.0 + sim::MoverFootprintRadius(mover));
  }
  traffic.shape = TrafficShape::kBox;
  EXPECT_EQ(SpawnTraffic(traffic, kStart, kGoal)[0].half_height_m, 0.4);
}

TEST(TrafficTest, EveryBehaviourAndShapeHasItsScenarioName) {
  const std::pair<const char*, TrafficBehaviour> behaviours[] = {
      {"random_walk", TrafficBehaviour::kRandomWalk},
      {"crossing", TrafficBehaviour::kCrossing},
      {"flow", TrafficBehaviour::kFlow},
      {"head_on", TrafficBehaviour::kHeadOn},
      {"overtaking", TrafficBehaviour::kOvertaking},
      {"reactive", TrafficBehaviour::kReactive}};
  for (const auto& [name, behaviour] : behaviours) {
    const Scenario scenario = LoadScenario(common::YamlDocument::Parse(
        std::string("traffic: {count: 2, behaviour: ") + name + ", shape: cart}\n", "t.yaml"));
    EXPECT_EQ(scenario.traffic.behaviour, behaviour) << name;
    EXPECT_EQ(scenario.traffic.shape, TrafficShape::kCart) << name;
  }
}

TEST(TrafficTest, ReactiveWalkersGoBackAndForthAcrossTheRouteKeepingTheirDistance) {
  TrafficSettings traffic;
  traffic.count = 3;
  traffic.behaviour = TrafficBehaviour::kReactive;
  for (const sim::MovingObstacle& mover : SpawnTraffic(traffic, kStart, kGoal)) {
    const auto& path = std::get<sim::WaypointMotion>(mover.motion);
    EXPECT_EQ(path.loop, sim::WaypointLoop::kPingPong);
    ASSERT_EQ(path.waypoints_W.size(), 2u);
    EXPECT_NEAR(std::abs(path.waypoints_W[0].y()), 6.0, 1e-9);
    EXPECT_NEAR(path.waypoints_W[0].y(), -path.waypoints_W[1].y(), 1e-9);
    EXPECT_EQ(mover.personal_distance_m, 0.8);
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

TEST(TrafficTest, ARunAddsItsTrafficClearOfTheWorldsObstacles) {
  // a forest: trees everywhere, and walkers placed only where their whole disc is free
  const Scenario scenario = LoadScenario(common::YamlDocument::Parse(
      "terrain: {type: forest, seed: 4, size: [30, 30]}\nrobot: {start: [-10, 0, 0]}\n"
      "goal: [10, 0]\n"
      "moving_obstacles: [{name: cart, motion: constant_velocity, velocity: [1, 0]}]\n"
      "traffic: {count: 6, speed: 1.2, seed: 3}\n",
      "traffic.yaml"));
  EXPECT_EQ(scenario.movers.size(), 1u);  // the file's own; traffic comes with the world
  const sim::TerrainWorld world =
      sim::GenerateTerrain(scenario.terrain, {scenario.start_W.position, scenario.goal_W});
  const Eigen::MatrixXf obstacles = sim::ObstacleHeightGrid(world);
  const std::vector<sim::MovingObstacle> movers = ScenarioMovers(scenario, world, obstacles);
  ASSERT_GE(movers.size(), 2u);
  EXPECT_EQ(movers[0].name, "cart");
  for (std::size_t k = 1; k < movers.size(); ++k) {
    const auto& walk = std::get<sim::RandomWalkMotion>(movers[k].motion);
    for (int ix = 0; ix < world.geometry.num_x; ++ix) {
      for (int iy = 0; iy < world.geometry.num_y; ++iy) {
        if ((world.geometry.CellCenter(ix, iy) - walk.area_centre_W).norm() <=
            walk.area_radius_m + movers[k].radius_m) {
          ASSERT_EQ(obstacles(ix, iy), 0.0f) << movers[k].name << " walks into an obstacle";
        }
      }
    }
  }
  // the resolved scenario keeps the settings: a replay spawns the same movers
  const Scenario replayed =
      LoadScenario(common::YamlDocument::Parse(ResolvedScenarioYaml(scenario), "resolved.yaml"));
  const std::vector<sim::MovingObstacle> again = ScenarioMovers(replayed, world, obstacles);
  ASSERT_EQ(again.size(), movers.size());
  EXPECT_EQ(std::get<sim::RandomWalkMotion>(again.back().motion).area_centre_W,
            std::get<sim::RandomWalkMotion>(movers.back().motion).area_centre_W);
  EXPECT_THROW(LoadScenario(common::YamlDocument::Parse("traffic: {speed: 5}\n", "bad.yaml")),
               common::InputError);
}

TEST(TrafficTest, StreamsHeadOnAndOvertakingMoveAsSpecified) {
  TrafficSettings traffic;
  traffic.count = 4;
  traffic.speed_m_s = 0.5;
  traffic.behaviour = TrafficBehaviour::kFlow;
  const auto flow = SpawnTraffic(traffic, kStart, kGoal);
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
  traffic.behaviour = TrafficBehaviour::kHeadOn;
  for (const sim::MovingObstacle& mover : SpawnTraffic(traffic, kStart, kGoal)) {
    sim::MoverTrack track(mover);
    const auto& motion = std::get<sim::ConstantVelocityMotion>(mover.motion);
    EXPECT_EQ(motion.velocity_W, Eigen::Vector2d(-0.5, 0.0));  // towards the start
    EXPECT_GE(motion.start_W.x(), 2.0 - 1e-9);                 // from the last 40 % of the route
    EXPECT_LE(std::abs(motion.start_W.y()), 1.0);
    const double t = motion.start_time_s + 4.0;
    EXPECT_NEAR(track.PlanarStateAt(t).p_W.x(), motion.start_W.x() - 2.0, 1e-9);
  }
  traffic.behaviour = TrafficBehaviour::kOvertaking;
  for (const sim::MovingObstacle& mover : SpawnTraffic(traffic, kStart, kGoal)) {
    const auto& motion = std::get<sim::ConstantVelocityMotion>(mover.motion);
    EXPECT_EQ(motion.velocity_W, Eigen::Vector2d(0.5, 0.0));  // towards the goal
    EXPECT_LE(motion.start_W.x(), 0.0 + 1e-9);                // from the first half
    EXPECT_EQ(motion.start_time_s, 0.0);
  }
}

}  // namespace
}  // namespace trav::scenarios
