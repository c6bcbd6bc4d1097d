// The LiDAR odometry on emulated MID-360 scans of a furnished room, the sensor moving and turning.
#include "mapping/lidar_odometry.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "common/input_error.h"
#include "sim/lidar/lidar_emulator.h"
#include "sim/lidar/ray_scene.h"
#include "tests/lidar/lidar_test_util.h"

namespace trav::mapping {
namespace {

using lidar::testing::MakePrimitive;
using lidar::testing::Plane;

// A 24 x 24 m room, 3 m high, with pillars and crates: structure along every axis.
lidar::RaySceneDescription Room() {
  lidar::RaySceneDescription room;
  room.meshes_W.push_back(Plane(12.0, 0.0));
  for (const double side : {-12.0, 12.0}) {
    room.primitives_W.push_back(
        MakePrimitive(common::ShapeType::kBox, {0.1, 12.0, 1.5}, {side, 0.0, 1.5}));
    room.primitives_W.push_back(
        MakePrimitive(common::ShapeType::kBox, {12.0, 0.1, 1.5}, {0.0, side, 1.5}));
  }
  const double pillars[][2] = {{4, 3}, {-3, 5}, {6, -4}, {-5, -6}, {9, 7}, {0, -8}};
  for (const auto& p : pillars) {
    room.primitives_W.push_back(
        MakePrimitive(common::ShapeType::kCylinder, {0.3, 1.5, 0.0}, {p[0], p[1], 1.5}));
  }
  const double crates[][3] = {{2, -2, 0.4}, {-6, 1, 0.6}, {7, 2, 0.3}, {-2, 8, 0.8}};
  for (const auto& c : crates) {
    room.primitives_W.push_back(
        MakePrimitive(common::ShapeType::kBox, {0.5, 0.7, c[2]}, {c[0], c[1], c[2]}));
  }
  return room;
}

// The sensor at time t: 0.3 m above the floor, starting at rest, accelerating at 1 m/s^2 to
// 1 m/s, along an arc of radius 5 m (0.2 rad per metre) from (-4, -3).
Eigen::Isometry3d SensorAt(double t_s) {
  const double s = t_s < 1.0 ? 0.5 * t_s * t_s : t_s - 0.5;  // arc length [m]
  const double yaw = 0.2 * s;
  Eigen::Isometry3d X_WL = Eigen::Isometry3d::Identity();
  X_WL.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  X_WL.translation() =
      Eigen::Vector3d(-4.0 + 5.0 * std::sin(yaw), -3.0 + 5.0 * (1.0 - std::cos(yaw)), 0.3);
  return X_WL;
}

// The odometry's poses X_OL (O = W at the first scan's end) after each of 50 scans.
std::vector<Eigen::Isometry3d> Drive() {
  const lidar::RayScene scene(Room());
  lidar::LidarEmulator emulator{lidar::LidarConfig{}};
  LidarOdometry odometry(LidarOdometryConfig{}, SensorAt(0.1));
  std::vector<Eigen::Isometry3d> poses;
  lidar::LidarFrame frame;
  for (int step = 0; step < 2500; ++step) {
    const double t = 0.002 * step;
    emulator.Scan(scene, t, t + 0.002, SensorAt(t));  // every 2 ms batch from its own pose
    if (!emulator.frame_ready()) continue;
    emulator.TakeFrame(&frame);
    poses.push_back(odometry.AddScan(frame.points_L.points, frame.points_L.time_offsets, 0.1));
  }
  return poses;
}

TEST(LidarOdometryTest, FollowsAMovingTurningSensorThroughARoom) {
  const std::vector<Eigen::Isometry3d> poses = Drive();
  ASSERT_EQ(poses.size(), 50u);
  // the pose after each scan against the true pose at the scan's end (4.5 m driven, 52 deg turned)
  double worst_m = 0.0, worst_deg = 0.0;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const Eigen::Isometry3d error = SensorAt(0.1 * (k + 1)).inverse() * poses[k];
    worst_m = std::max(worst_m, error.translation().norm());
    worst_deg = std::max(worst_deg, Eigen::AngleAxisd(error.linear()).angle() * 180.0 / M_PI);
  }
  EXPECT_LT(worst_m, 0.05);
  EXPECT_LT(worst_deg, 0.5);
  // it tracked the motion rather than standing still: the last pose is metres from the first
  EXPECT_GT((poses.front().inverse() * poses.back()).translation().norm(), 3.5);
}

TEST(LidarOdometryTest, RepeatsBitForBit) {
  const std::vector<Eigen::Isometry3d> a = Drive();
  const std::vector<Eigen::Isometry3d> b = Drive();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_TRUE(a[k].isApprox(b[k], 0.0)) << k;
}

TEST(LidarOdometryTest, ABadConfigIsAnInputErrorNamingTheKey) {
  LidarOdometryConfig config;
  config.max_range_m = 0.5;
  EXPECT_THROW(LidarOdometry(config, Eigen::Isometry3d::Identity()), common::InputError);
}

}  // namespace
}  // namespace trav::mapping
