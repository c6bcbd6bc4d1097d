// Collisions with movers are told apart by who closed the gap, and near misses are counted.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "common/yaml_reader.h"
#include "scenarios/run/scenario.h"
#include "scenarios/run/scenario_run.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;

RunSummary RunYaml(const std::string& yaml) {
  const Scenario scenario = LoadScenario(common::YamlDocument::Parse(yaml, "collision.yaml"));
  const fs::path out =
      fs::temp_directory_path() / ("trav_collision_" + std::to_string(getpid()) + "_" +
                                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::create_directories(out);
  const RunSummary summary =
      RunScenario(scenario, RobotModelPath(scenario, TRAV_MODELS_DIR), out.string());
  fs::remove_all(out);
  return summary;
}

constexpr char kFlat[] =
    "terrain: {type: flat, size: [20, 20]}\nrobot: {start: [0, 0, 0]}\nduration: 8\n"
    "lidar: {enabled: false}\nvideo: {enabled: false}\n";

TEST(CollisionCauseTest, AMoverRunningIntoAStoppedRobotIsTheMoversCollision) {
  const RunSummary summary =
      RunYaml(std::string(kFlat) +
              "mode: drive\ndrive: [{v: 0, omega: 0, duration: 8}]\n"
              "moving_obstacles: [{name: cart, shape: box, half_height: 0.4, box_half_extents: "
              "[0.3, 0.3], motion: constant_velocity, start: [4, 0], velocity: [-1, 0]}]\n");
  ASSERT_EQ(summary.outcome, Outcome::kCollision);
  ASSERT_TRUE(summary.collision.has_value());
  EXPECT_TRUE(summary.collision->mover);
  EXPECT_EQ(summary.collision->target, "cart");
  EXPECT_EQ(summary.collision->caused_by, "mover");
  EXPECT_LT(summary.collision->robot_speed_m_s, 0.05);
  EXPECT_NEAR(summary.collision->relative_speed_m_s, 1.0, 0.1);
  // the cart's front (x = 4 - t + 0.3 ... ) meets the robot's front (0.28 m ahead) after ~3.4 s
  EXPECT_NEAR(summary.collision->time_s, 3.4, 0.3);
}

TEST(CollisionCauseTest, TheRobotDrivingIntoAStandingMoverIsTheRobotsCollision) {
  const RunSummary summary =
      RunYaml(std::string(kFlat) +
              "mode: drive\ndrive: [{v: 1, omega: 0, duration: 8}]\n"
              "moving_obstacles: [{name: post, shape: cylinder, radius: 0.2, half_height: 0.5, "
              "motion: waypoints, waypoints: [[3, 0]]}]\n");
  ASSERT_EQ(summary.outcome, Outcome::kCollision);
  EXPECT_EQ(summary.collision->caused_by, "robot");
  EXPECT_GT(summary.collision->robot_speed_m_s, 0.5);
}

TEST(CollisionCauseTest, APedestrianPassingCloseIsOneNearMiss) {
  // a pedestrian comes the other way 0.9 m beside the robot's line
  const RunSummary summary =
      RunYaml(std::string(kFlat) +
              "mode: navigate\nmapping: {method: ground-truth}\ngoal: [6, 0]\n"
              "navigation: {near_miss_clearance: 1.0}\n"
              "moving_obstacles: [{name: walker, motion: constant_velocity, start: [8, 0.9], "
              "velocity: [-1, 0]}]\n");
  ASSERT_TRUE(summary.navigation.has_value());
  EXPECT_LT(summary.navigation->min_mover_clearance_m, 1.0);  // the planner keeps 0.7 m
  EXPECT_EQ(summary.navigation->near_misses, 1);
}

}  // namespace
}  // namespace trav::scenarios
