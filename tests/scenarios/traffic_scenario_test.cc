// The scenario keys of traffic, and the traffic a run spawns for its world.
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <gtest/gtest.h>

#include "common/input_error.h"
#include "common/yaml_reader.h"
#include "scenarios/run/scenario.h"
#include "scenarios/run/scenario_run.h"
#include "sim/terrain.h"
#include "sim/terrain_geometry.h"

namespace trav::scenarios {
namespace {

TEST(TrafficScenarioTest, EveryBehaviourAndShapeHasItsScenarioName) {
  const std::pair<const char*, sim::TrafficBehaviour> behaviours[] = {
      {"random_walk", sim::TrafficBehaviour::kRandomWalk},
      {"crossing", sim::TrafficBehaviour::kCrossing},
      {"flow", sim::TrafficBehaviour::kFlow},
      {"head_on", sim::TrafficBehaviour::kHeadOn},
      {"overtaking", sim::TrafficBehaviour::kOvertaking},
      {"reactive", sim::TrafficBehaviour::kReactive}};
  for (const auto& [name, behaviour] : behaviours) {
    const Scenario scenario = LoadScenario(common::YamlDocument::Parse(
        std::string("traffic: {count: 2, behaviour: ") + name + ", shape: cart}\n", "t.yaml"));
    EXPECT_EQ(scenario.traffic.behaviour, behaviour) << name;
    EXPECT_EQ(scenario.traffic.shape, sim::TrafficShape::kCart) << name;
  }
}

TEST(TrafficScenarioTest, ARunAddsItsTrafficClearOfTheWorldsObstacles) {
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

}  // namespace
}  // namespace trav::scenarios
