#include "sim/lidar/lidar_emulator.h"

#include <cmath>
#include <utility>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/check.h"
#include "common/input_error.h"
#include "tests/lidar/lidar_test_util.h"

namespace trav::lidar {
namespace {

using testing::At;
using ::testing::HasSubstr;
using testing::MakePrimitive;
using testing::Plane;
using ::testing::StartsWith;
using ::testing::ThrowsMessage;

// Runs the emulator standing still at X_WL for one frame, in 2 ms batches.
LidarFrame OneFrame(const RayScene& scene, const LidarConfig& config,
                    const Eigen::Isometry3d& X_WL) {
  LidarEmulator dut(config);
  for (int step = 0; step < 50; ++step) dut.Scan(scene, step * 0.002, (step + 1) * 0.002, X_WL);
  EXPECT_TRUE(dut.frame_ready());
  LidarFrame frame;
  dut.TakeFrame(&frame);
  return frame;
}

LidarConfig Noiseless() {
  LidarConfig config;
  config.range_noise_m = 0.0;
  config.angular_noise_deg = 0.0;
  return config;
}

// A closed sphere of radius 20 m around the origin: every ray returns. Its centre is a few
// centimetres off the origin, so that no ray of the pattern runs exactly through an edge shared by
// two of its triangles (such a ray can slip through, RayScene::Cast).
RayScene Enclosure() {
  RaySceneDescription description;
  description.primitives_W.push_back(
      MakePrimitive(common::ShapeType::kSphere, {20, 0, 0}, {0.013, -0.021, 0.007}));
  return RayScene(description);
}

TEST(LidarEmulatorTest, AFrameHasTwentyThousandPointsWithTimesAndLines) {
  const RayScene scene = Enclosure();
  const LidarFrame frame = OneFrame(scene, Noiseless(), Eigen::Isometry3d::Identity());
  EXPECT_EQ(frame.rays, 20000);
  ASSERT_EQ(frame.points_L.size(), 20000);
  EXPECT_EQ(frame.points_L.frame_id, "L");
  EXPECT_EQ(frame.points_L.stamp_s, 0.0);
  // 5 microseconds per point, lines 0..3 in turn
  EXPECT_FLOAT_EQ(frame.points_L.time_offsets[1], 5e-6f);
  EXPECT_FLOAT_EQ(frame.points_L.time_offsets[19999], 19999 * 5e-6f);
  EXPECT_EQ(frame.points_L.line_ids[6], 2);
  EXPECT_EQ(frame.batch_poses_W.size(), 50u);
}

TEST(LidarEmulatorTest, TakingAFrameBeforeOneIsCompleteIsAPreconditionError) {
  const RayScene scene = Enclosure();
  LidarEmulator dut(Noiseless());
  LidarFrame frame;
  EXPECT_THROW(dut.TakeFrame(&frame), common::PreconditionError);
  dut.Scan(scene, 0.0, 0.05, Eigen::Isometry3d::Identity());  // half a frame
  EXPECT_FALSE(dut.frame_ready());
  EXPECT_THROW(dut.TakeFrame(&frame), common::PreconditionError);
}

TEST(LidarEmulatorTest, RangeNoiseHasTheConfiguredStandardDeviation) {
  RaySceneDescription description;
  description.meshes_W.push_back(Plane(500.0, 0.0));
  const RayScene scene(description);
  LidarConfig config = Noiseless();
  config.range_noise_m = 0.05;
  config.range_max_m = 100.0;
  const LidarFrame frame = OneFrame(scene, config, At({0, 0, 1}));
  // the true range of a point is 1 / sin(depression) along its direction
  double sum = 0.0, sum2 = 0.0;
  const Eigen::Index n = frame.points_L.size();
  ASSERT_GT(n, 2000);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3f p = frame.points_L.points.col(i);
    const double range = p.norm();
    const double residual = range - 1.0 / (-p.z() / range);
    sum += residual;
    sum2 += residual * residual;
  }
  const double mean = sum / n;
  const double sigma = std::sqrt(sum2 / n - mean * mean);
  EXPECT_LT(std::abs(mean), 4.0 * 0.05 / std::sqrt(static_cast<double>(n)));
  EXPECT_NEAR(sigma, 0.05, 0.05 * 0.06);
}

TEST(LidarEmulatorTest, DropoutAndOcclusionRemoveTheConfiguredShare) {
  const RayScene scene = Enclosure();
  LidarConfig config = Noiseless();
  config.dropout = 0.3;
  const LidarFrame dropped = OneFrame(scene, config, Eigen::Isometry3d::Identity());
  EXPECT_NEAR(dropped.dropped.dropout / 20000.0, 0.3, 0.015);
  EXPECT_EQ(dropped.points_L.size() + dropped.dropped.dropout, 20000);

  config.dropout = 0.0;
  config.occlusion = 0.15;
  const LidarFrame occluded = OneFrame(scene, config, Eigen::Isometry3d::Identity());
  // sectors may overlap: up to 15 % of the azimuth (and of the evenly spread points)
  EXPECT_LE(occluded.dropped.occluded / 20000.0, 0.155);
  EXPECT_GT(occluded.dropped.occluded / 20000.0, 0.05);
  EXPECT_EQ(occluded.points_L.size() + occluded.dropped.occluded, 20000);
}

// A wall x = distance_m facing the sensor at the origin (a thin box), of diffuse reflectance rho.
RayScene Wall(double distance_m, float rho) {
  RaySceneDescription description;
  description.primitives_W.push_back(
      MakePrimitive(common::ShapeType::kBox, {0.01, 400, 400}, {distance_m + 0.01, 0, 0}));
  description.reflectance = {rho};
  return RayScene(description);
}

// The detection reach of the default config at an effective reflectance (LidarConfig::detection).
double Reach(double effective) {
  return 40.0 * std::pow(effective / 0.1, std::log(70.0 / 40.0) / std::log(8.0));
}

TEST(LidarEmulatorTest, ReflectivityIsTheReflectanceTimesTheCosineOfIncidence) {
  LidarConfig config = Noiseless();
  config.reflectivity_noise = 0.0;
  config.incidence_floor = 0.0;
  const LidarFrame frame = OneFrame(Wall(5.0, 0.6f), config, Eigen::Isometry3d::Identity());
  ASSERT_GT(frame.points_L.size(), 5000);
  ASSERT_EQ(frame.points_L.reflectivity.size(), frame.points_L.size());
  for (Eigen::Index i = 0; i < frame.points_L.size(); ++i) {
    const Eigen::Vector3f p = frame.points_L.points.col(i);
    const double cos_incidence = p.x() / p.norm();  // the wall's normal is -x
    ASSERT_NEAR(frame.points_L.reflectivity[i], 150.0 * 0.6 * cos_incidence, 0.5 + 1e-3) << i;
    ASSERT_EQ(frame.points_L.tags[i], 0);
  }
  // a rough surface presents no less than the floor's cosine
  config.incidence_floor = 0.3;
  const LidarFrame rough = OneFrame(Wall(5.0, 0.6f), config, Eigen::Isometry3d::Identity());
  int grazing = 0;
  for (Eigen::Index i = 0; i < rough.points_L.size(); ++i) {
    const Eigen::Vector3f p = rough.points_L.points.col(i);
    const double c = std::max(0.3, static_cast<double>(p.x() / p.norm()));
    grazing += p.x() / p.norm() < 0.3f ? 1 : 0;
    ASSERT_NEAR(rough.points_L.reflectivity[i], 150.0 * 0.6 * c, 0.5 + 1e-3) << i;
  }
  EXPECT_GT(grazing, 100);
  // with noise: 5 % of the value, unbiased
  config.reflectivity_noise = 0.05;
  const LidarFrame noisy = OneFrame(Wall(5.0, 0.6f), config, Eigen::Isometry3d::Identity());
  double sum = 0.0, sum2 = 0.0;
  for (Eigen::Index i = 0; i < noisy.points_L.size(); ++i) {
    const Eigen::Vector3f p = noisy.points_L.points.col(i);
    const double c = std::max(0.3, static_cast<double>(p.x() / p.norm()));
    const double ratio = noisy.points_L.reflectivity[i] / (150.0 * 0.6 * c) - 1.0;
    sum += ratio;
    sum2 += ratio * ratio;
  }
  const double n = static_cast<double>(noisy.points_L.size());
  EXPECT_NEAR(sum / n, 0.0, 0.005);
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.05, 0.01);  // with the rounding to whole steps
}

// The detection model's shortcut (certain echoes below half the reach) against the formula it
// spares, bit for bit, over reflectances and ranges that cross every bin and the whole step.
TEST(DetectionModelTest, EqualsTheLogisticFormulaToTheBit) {
  for (const auto& [r10_m, r80_m] : {std::pair{40.0, 70.0}, {40.0, 40.0}, {5.0, 200.0}}) {
    LidarConfig config;
    config.range_at_10_percent_m = r10_m;
    config.range_at_80_percent_m = r80_m;
    const DetectionModel model(config);
    const double k = std::log(r80_m / r10_m) / std::log(8.0);
    int certain = 0;
    for (int i = 0; i <= 1000; ++i) {
      const double rho = i / 1000.0;
      const double reach_m = r10_m * std::pow(std::max(rho, 1e-6) / 0.1, k);
      for (double range_m = 0.05; range_m < 150.0; range_m *= 1.05) {
        const double formula = 1.0 / (1.0 + std::exp((range_m - reach_m) / (0.05 * reach_m / 4.0)));
        ASSERT_EQ(model.Probability(rho, range_m), formula) << rho << " " << range_m;
        certain += formula == 1.0;
      }
    }
    EXPECT_GT(certain, 1000);
  }
  LidarConfig off;
  off.detection = false;
  EXPECT_EQ(DetectionModel(off).Probability(0.01, 500.0), 1.0);
}

TEST(LidarEmulatorTest, DarkAndGrazingSurfacesReturnOnlyWithinTheirDetectionReach) {
  LidarConfig config = Noiseless();
  config.incidence_floor = 0.0;
  for (const auto& [distance_m, rho] : {std::pair{30.0, 0.05f}, {30.0, 0.8f}, {60.0, 0.8f}}) {
    SCOPED_TRACE(::testing::Message() << "wall at " << distance_m << " m, reflectance " << rho);
    const LidarFrame frame = OneFrame(Wall(distance_m, rho), config, Eigen::Isometry3d::Identity());
    // every returned point lies within its reach (the chance of a return is 1e-5 at 1.15 R)
    for (Eigen::Index i = 0; i < frame.points_L.size(); ++i) {
      const Eigen::Vector3f p = frame.points_L.points.col(i);
      ASSERT_LT(p.norm(), 1.15 * Reach(rho * p.x() / p.norm()));
    }
    // the rays well within their reach all return, those well beyond none
    const auto pattern = TablePattern::Mid360();
    int sure = 0, possible = 0;
    for (int i = 0; i < 20000; ++i) {
      const Eigen::Vector3f d = pattern->Ray(i).direction_L;
      if (d.x() <= 0.0f) continue;
      const double range = distance_m / d.x();
      if (range > config.range_max_m) continue;
      const double reach = Reach(rho * d.x());
      sure += range < 0.85 * reach ? 1 : 0;
      possible += range < 1.15 * reach ? 1 : 0;
    }
    EXPECT_GE(frame.points_L.size(), sure);
    EXPECT_LE(frame.points_L.size(), possible);
    EXPECT_EQ(frame.points_L.size() + frame.dropped.weak + frame.dropped.miss, 20000);
  }
  // a dark wall at 30 m returns only near its normal; a bright one at 60 m still returns
  EXPECT_LT(OneFrame(Wall(30.0, 0.05f), config, Eigen::Isometry3d::Identity()).points_L.size(),
            OneFrame(Wall(30.0, 0.8f), config, Eigen::Isometry3d::Identity()).points_L.size() / 4);
  LidarConfig ideal = config;
  ideal.detection = false;
  const LidarFrame all = OneFrame(Wall(30.0, 0.05f), ideal, Eigen::Isometry3d::Identity());
  EXPECT_EQ(all.dropped.weak, 0);
}

TEST(LidarEmulatorTest, MissesAndTheBlindZoneGiveNoPoints) {
  RaySceneDescription description;
  // a small box 5 cm in front of the sensor (inside the blind zone) and open sky elsewhere
  description.primitives_W.push_back(
      MakePrimitive(common::ShapeType::kBox, {0.01, 0.5, 0.5}, {0.06, 0, 0}));
  description.meshes_W.push_back(Plane(100.0, -1.0));
  const RayScene scene(description);
  const LidarFrame frame = OneFrame(scene, Noiseless(), Eigen::Isometry3d::Identity());
  EXPECT_GT(frame.dropped.blind, 100);
  EXPECT_GT(frame.dropped.miss, 1000);
  EXPECT_EQ(frame.points_L.size() + frame.dropped.blind + frame.dropped.miss + frame.dropped.weak,
            20000);
  for (Eigen::Index i = 0; i < frame.points_L.size(); ++i) {
    ASSERT_GE(frame.points_L.points.col(i).norm(), 0.1f);
  }
}

TEST(LidarEmulatorTest, SameSeedSameFramesOtherSeedOtherNoise) {
  const RayScene scene = Enclosure();
  LidarConfig config;
  config.dropout = 0.1;
  const LidarFrame a = OneFrame(scene, config, Eigen::Isometry3d::Identity());
  const LidarFrame b = OneFrame(scene, config, Eigen::Isometry3d::Identity());
  config.seed = 2;
  const LidarFrame c = OneFrame(scene, config, Eigen::Isometry3d::Identity());
  ASSERT_EQ(a.points_L.size(), b.points_L.size());
  EXPECT_TRUE((a.points_L.points.array() == b.points_L.points.array()).all());
  EXPECT_FALSE(a.points_L.size() == c.points_L.size() &&
               (a.points_L.points.array() == c.points_L.points.array()).all());
}

TEST(LidarEmulatorTest, MotionDistortionIsRealAndCorrectedByPerPointPoses) {
  // a wall facing the sensor at x = 10 m; the sensor drives towards it at 2 m/s
  RaySceneDescription description;
  description.primitives_W.push_back(
      MakePrimitive(common::ShapeType::kBox, {0.5, 20, 20}, {10.5, 0, 0}));
  const RayScene scene(description);
  LidarEmulator dut(Noiseless());
  const double speed = 2.0;
  for (int step = 0; step < 50; ++step) {
    const double t = step * 0.002;
    dut.Scan(scene, t, t + 0.002, At({speed * t, 0, 0}));
  }
  ASSERT_TRUE(dut.frame_ready());
  LidarFrame frame;
  dut.TakeFrame(&frame);
  const Eigen::Matrix3Xf corrected_W = PointsInWorld(frame);
  int on_wall = 0;
  double largest_offset = 0.0;
  for (Eigen::Index i = 0; i < frame.points_L.size(); ++i) {
    if (std::abs(corrected_W(0, i) - 10.0f) > 0.01f) continue;  // floor-less scene: only the wall
    ++on_wall;
    // with its own pose every point lies on the wall
    EXPECT_NEAR(corrected_W(0, i), 10.0f, 1e-4f);
    // with the frame-start pose it is short of the wall by the distance driven since the start
    const Eigen::Vector3d start_W =
        frame.X_WL_start() * frame.points_L.points.col(i).cast<double>();
    const double driven =
        frame.PoseOfPoint(i).translation().x() - frame.X_WL_start().translation().x();
    EXPECT_NEAR(start_W.x(), 10.0 - driven, 1e-4);
    largest_offset = std::max(largest_offset, driven);
  }
  EXPECT_GT(on_wall, 1000);
  EXPECT_NEAR(largest_offset, speed * 0.098, 1e-9);
}

TEST(LidarEmulatorTest, InvalidSettingsAreInputErrors) {
  LidarConfig config;
  config.range_max_m = -1.0;
  EXPECT_THAT([&] { LidarEmulator dut(config); },
              ThrowsMessage<common::InputError>(
                  StartsWith("range_max: value -1.000000 must be > range_min")));
  config = LidarConfig();
  config.points_per_second = 0.0;
  EXPECT_THAT([&] { LidarEmulator dut(config); },
              ThrowsMessage<common::InputError>(StartsWith("rate: ")));
  config = LidarConfig();
  config.pattern_table = "/nonexistent/mid360.csv";
  EXPECT_THAT([&] { LidarEmulator dut(config); },
              ThrowsMessage<common::InputError>(HasSubstr("cannot open scan table")));
}

}  // namespace
}  // namespace trav::lidar
