// LidarPipeline: the same frames, bit for bit, whether the steps are scanned on the loop's thread
// or on the worker, with a mover that moves every step (the closed loop's identity test is in
// navigation_test.cc).
#include "scenarios/run/lidar_pipeline.h"

#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "common/mesh.h"

namespace trav::scenarios {
namespace {

constexpr double kStep_s = 0.002;

// The cube at step k: 4 m ahead of the sensor, sliding sideways 1 cm per step.
Eigen::Isometry3d MoverPose(int k) {
  Eigen::Isometry3d X_WI = Eigen::Isometry3d::Identity();
  X_WI.translation() = Eigen::Vector3d(4.0, -1.0 + 0.01 * k, 0.5);
  return X_WI;
}

// A floor (a flat box top at z = 0) and a 1 m cube that moves across the sensor's view.
std::unique_ptr<lidar::RayScene> Scene() {
  lidar::RaySceneDescription description;
  common::Primitive floor;
  floor.size = Eigen::Vector3d(20.0, 20.0, 0.5);
  floor.X_WO.translation() = Eigen::Vector3d(0.0, 0.0, -0.5);
  description.primitives_W.push_back(floor);
  common::Primitive cube;
  cube.size = Eigen::Vector3d(0.5, 0.5, 0.5);
  description.moving_meshes_I.push_back(common::PrimitiveMesh(cube));
  description.X_WI.push_back(MoverPose(0));
  return std::make_unique<lidar::RayScene>(description);
}

struct Scanned {
  std::vector<int> frame_steps;  // the steps that completed a frame
  std::vector<lidar::LidarFrame> frames;
  std::vector<double> step_ms;
};

// 0.35 s of steps (three frames and a half) from a sensor driving forward at 1 m/s.
Scanned ScanSteps(bool worker_thread) {
  lidar::LidarConfig config;
  config.seed = 7;
  LidarPipeline pipeline(Scene(), std::make_unique<lidar::LidarEmulator>(config), worker_thread);
  EXPECT_EQ(pipeline.threaded(), worker_thread);
  Scanned scanned;
  for (int k = 0; k < 175; ++k) {
    ScanStep step;
    step.t_begin_s = k * kStep_s;
    step.t_end_s = (k + 1) * kStep_s;
    step.X_WL.translation() = Eigen::Vector3d(k * kStep_s, 0.0, 0.4);
    step.movers_X_WI = {MoverPose(k)};
    if (!pipeline.Submit(step)) continue;
    scanned.frame_steps.push_back(k);
    scanned.frames.emplace_back();
    pipeline.TakeFrame(&scanned.frames.back());
  }
  pipeline.TakeStepTimes(&scanned.step_ms);
  return scanned;
}

TEST(LidarPipelineTest, TheWorkerScansTheSameFramesBitForBit) {
  const Scanned inline_scan = ScanSteps(false);
  const Scanned worker_scan = ScanSteps(true);
  // 20,000 rays per frame at 200,000 per second: every 50th step completes one
  EXPECT_EQ(inline_scan.frame_steps, (std::vector<int>{49, 99, 149}));
  EXPECT_EQ(worker_scan.frame_steps, inline_scan.frame_steps);
  EXPECT_EQ(inline_scan.step_ms.size(), 175u);
  EXPECT_EQ(worker_scan.step_ms.size(), 175u);
  ASSERT_EQ(worker_scan.frames.size(), 3u);
  for (std::size_t f = 0; f < 3; ++f) {
    const lidar::LidarFrame& a = inline_scan.frames[f];
    const lidar::LidarFrame& b = worker_scan.frames[f];
    EXPECT_EQ(a.index, static_cast<std::int64_t>(f));
    EXPECT_EQ(b.index, a.index);
    EXPECT_EQ(b.rays, a.rays);
    ASSERT_GT(a.points_L.size(), 1000);
    ASSERT_EQ(b.points_L.size(), a.points_L.size());
    EXPECT_TRUE(b.points_L.points == a.points_L.points);
    EXPECT_TRUE(b.points_L.time_offsets == a.points_L.time_offsets);
    EXPECT_TRUE(b.points_L.reflectivity == a.points_L.reflectivity);
    EXPECT_EQ(b.batch_times_s, a.batch_times_s);
    EXPECT_TRUE(b.X_WL_end.matrix() == a.X_WL_end.matrix());
  }
}

TEST(LidarPipelineTest, TheMoverIsWhereItsStepPutsIt) {
  // the cube crosses the view: the points that hit it (x about 3.5 m ahead, above the floor) move
  // sideways from frame to frame with the cube, 0.5 m per 50 steps
  const Scanned scanned = ScanSteps(true);
  std::vector<double> mean_y;
  for (const lidar::LidarFrame& frame : scanned.frames) {
    const Eigen::Matrix3Xf points_W = lidar::PointsInWorld(frame);
    double sum = 0.0;
    int count = 0;
    for (Eigen::Index i = 0; i < points_W.cols(); ++i) {
      if (points_W(2, i) > 0.2f && points_W(0, i) < 4.6f) {
        sum += points_W(1, i);
        ++count;
      }
    }
    ASSERT_GT(count, 20);
    mean_y.push_back(sum / count);
  }
  EXPECT_NEAR(mean_y[1] - mean_y[0], 0.5, 0.1);
  EXPECT_NEAR(mean_y[2] - mean_y[1], 0.5, 0.1);
}

}  // namespace
}  // namespace trav::scenarios
