// The LiDAR against the simulated world: what it sees, and that it never sees the robot.
#include <string>
#include <vector>

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

// Number of points of `points_W` inside the mover's box at X_WO, grown by 1 cm, but for its
// lowest 5 cm (the ground under an empty footprint returns points there).
int PointsOnBox(const Eigen::Matrix3Xf& points_W, const MovingObstacle& box,
                const Eigen::Isometry3d& X_WO) {
  const Eigen::Vector3d half(box.box_half_extents_m.x() + 0.01, box.box_half_extents_m.y() + 0.01,
                             box.half_height_m + 0.01);
  const double bottom_O = 0.05 - box.half_height_m;
  const Eigen::Isometry3d X_OW = X_WO.inverse();
  int count = 0;
  for (Eigen::Index i = 0; i < points_W.cols(); ++i) {
    const Eigen::Vector3d p_O = X_OW * points_W.col(i).cast<double>();
    if ((p_O.cwiseAbs().array() <= half.array()).all() && p_O.z() > bottom_O) ++count;
  }
  return count;
}

TEST(LidarWorldTest, TheLidarSeesAMoverWhereItIsNow) {
  TerrainConfig config;
  config.type = TerrainType::kFlat;
  config.size_m = {12, 12};
  const TerrainWorld world = GenerateTerrain(config);
  MovingObstacle box;
  box.name = "box";
  box.shape = MoverShape::kBox;
  box.box_half_extents_m = {0.3, 0.3};
  box.half_height_m = 0.5;
  box.motion = ConstantVelocityMotion{{3.0, 0.0}, {0.0, 1.0}, 0.0};  // crosses in front of it
  const std::vector<MovingObstacle> movers = {box};
  const lidar::RaySceneDescription description = RaySceneOf(world, movers);
  ASSERT_EQ(description.moving_meshes_I.size(), 1u);
  EXPECT_TRUE(description.X_WI[0].isApprox(MoverPoseAt(box, 0.0, world)));
  lidar::RayScene scene(description);
  EXPECT_EQ(scene.num_objects(), 2);  // ground and the box

  lidar::LidarConfig lidar_config;
  lidar_config.range_noise_m = 0.0;
  lidar_config.angular_noise_deg = 0.0;
  lidar::LidarEmulator lidar(lidar_config);
  Eigen::Isometry3d X_WL = Eigen::Isometry3d::Identity();
  X_WL.translation() = Eigen::Vector3d(0.0, 0.0, 0.3);
  // one 100 ms frame with the box at its pose at `t_s`, cast in 2 ms batches
  MoverTrack track(box);
  auto scan_frame = [&](double t_s) {
    scene.SetMovingPose(0, track.PoseAt(t_s, world));
    lidar::LidarFrame frame;
    for (int step = 0; step < 50 && !lidar.frame_ready(); ++step) {
      lidar.Scan(scene, t_s + 0.002 * step, t_s + 0.002 * (step + 1), X_WL);
    }
    EXPECT_TRUE(lidar.frame_ready());
    lidar.TakeFrame(&frame);
    return lidar::PointsInWorld(frame);
  };
  const Eigen::Isometry3d X_WO_before = track.PoseAt(0.0, world);
  const Eigen::Isometry3d X_WO_after = track.PoseAt(2.0, world);  // at (3, 2)
  const Eigen::Matrix3Xf before_W = scan_frame(0.0);
  EXPECT_GT(PointsOnBox(before_W, box, X_WO_before), 100);
  EXPECT_EQ(PointsOnBox(before_W, box, X_WO_after), 0);
  const Eigen::Matrix3Xf after_W = scan_frame(2.0);
  EXPECT_GT(PointsOnBox(after_W, box, X_WO_after), 100);
  EXPECT_EQ(PointsOnBox(after_W, box, X_WO_before), 0);
}

}  // namespace
}  // namespace trav::sim
