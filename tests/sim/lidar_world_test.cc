// The LiDAR against the simulated world: what it sees, and that it never sees the robot.
#include <string>

#include <gtest/gtest.h>

#include "sim/lidar/lidar_emulator.h"
#include "sim/simulation.h"
#include "sim/terrain_geometry.h"

namespace trav::sim {
namespace {

TEST(LidarWorldTest, RaySceneHoldsTheGroundAndEveryObstacle) {
  TerrainConfig config;
  config.type = TerrainType::kForest;
  config.size_m = {20, 20};
  const TerrainWorld world = GenerateTerrain(config);
  const lidar::RaySceneDescription description = RaySceneOf(world);
  ASSERT_EQ(description.meshes_W.size(), 1u);
  EXPECT_EQ(description.meshes_W[0].triangles.cols(), 2 * 200 * 200);
  EXPECT_EQ(description.primitives_W.size(), world.obstacles.size());
  const lidar::RayScene scene(description);
  EXPECT_EQ(scene.num_objects(), 1 + static_cast<int>(world.obstacles.size()));
}

TEST(LidarWorldTest, NoPointFallsOnTheRobotsOwnBody) {
  TerrainConfig config;
  config.type = TerrainType::kHilly;
  config.size_m = {20, 20};
  const TerrainWorld world = GenerateTerrain(config);
  WorldOptions options;
  options.robot_model_path = std::string(TRAV_MODELS_DIR) + "/scout_mini.xml";
  Simulation sim(world, common::Pose2{}, options);
  const lidar::RayScene scene(RaySceneOf(world));
  lidar::LidarConfig lidar_config;
  lidar_config.range_noise_m = 0.0;
  lidar_config.angular_noise_deg = 0.0;
  lidar::LidarEmulator lidar(lidar_config);
  lidar::LidarFrame frame;
  for (int step = 0; step < 100; ++step) {
    lidar.Scan(scene, sim.time(), sim.time() + sim.timestep(), sim.LidarPose());
    ASSERT_EQ(sim.Step(), StepStatus::kOk);
    if (lidar.frame_ready()) lidar.TakeFrame(&frame);
  }
  ASSERT_GT(frame.points_L.size(), 1000);
  // every point, seen from the base, lies outside the robot's bounding box (0.63 x 0.58 x 0.25 m)
  const Eigen::Isometry3d X_BW = sim.State().X_WB.inverse();
  const Eigen::Matrix3Xf points_W = lidar::PointsInWorld(frame);
  for (Eigen::Index i = 0; i < points_W.cols(); ++i) {
    const Eigen::Vector3d p_B = X_BW * points_W.col(i).cast<double>();
    const bool inside =
        std::abs(p_B.x()) < 0.32 && std::abs(p_B.y()) < 0.29 && p_B.z() > -0.08 && p_B.z() < 0.25;
    ASSERT_FALSE(inside) << "point " << i << " at " << p_B.transpose() << " in B";
  }
}

}  // namespace
}  // namespace trav::sim
