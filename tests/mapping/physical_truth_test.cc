#include "mapping/physical_truth.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include <gtest/gtest.h>

#include "mapping/traversability_mapper.h"

namespace trav::mapping {
namespace {

constexpr double kDeg = M_PI / 180.0;
const common::GridGeometry kWorld =
    common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(6, 6), 0.1);
const common::GridGeometry kMap =
    common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(6, 6), 0.2);

Eigen::MatrixXf Sampled(const std::function<double(double, double)>& height) {
  Eigen::MatrixXf h(kWorld.num_x, kWorld.num_y);
  for (int ix = 0; ix < kWorld.num_x; ++ix) {
    for (int iy = 0; iy < kWorld.num_y; ++iy) {
      const Eigen::Vector2d p = kWorld.CellCenter(ix, iy);
      h(ix, iy) = static_cast<float>(height(p.x(), p.y()));
    }
  }
  return h;
}

const Eigen::MatrixXf kFlat = Sampled([](double, double) { return 0.0; });

// A plane rising along +x at `angle_deg`.
Eigen::MatrixXf Slope(double angle_deg) {
  return Sampled([angle_deg](double x, double) { return std::tan(angle_deg * kDeg) * x; });
}

PoseAssessment At(const Eigen::MatrixXf& ground, const Eigen::MatrixXf& obstacles, double x,
                  double yaw_deg) {
  const RestingSurface surface{kWorld, ground, obstacles};
  return AssessPose(surface, Eigen::Vector2d(x, 0.0), yaw_deg * kDeg, RestingBody{},
                    GroundTruthConfig{});
}

TEST(PhysicalTruthTest, FlatGroundIsFreeAtEveryHeadingAndTheRimIsUnknown) {
  const common::GridLayers truth =
      ComputePhysicalTruth(kMap, kWorld, kFlat, kFlat, RestingBody{}, GroundTruthConfig{});
  const Eigen::MatrixXf& cost = truth.Layer(layers::kTraversability);
  EXPECT_EQ(cost(15, 15), 0.0f);
  EXPECT_EQ(truth.Layer(kTraversableHeadings)(15, 15), 16.0f);
  EXPECT_EQ(truth.Layer(HeadingLayer(5))(15, 15), 0.0f);
  // a robot centred on the border cell would stand half off the world
  EXPECT_TRUE(std::isnan(cost(0, 15)));
  EXPECT_TRUE(std::isnan(cost(1, 15)));  // 0.2 m in: the wheels (0.31 m) still reach out
  EXPECT_FALSE(std::isnan(cost(2, 15)));
}

TEST(PhysicalTruthTest, AFifteenDegreeSlopeIsTraversableAlongAndAcross) {
  const Eigen::MatrixXf ground = Slope(15.0);
  const PoseAssessment up = At(ground, kFlat, 0.0, 0.0);
  EXPECT_NEAR(up.pitch_rad, 15.0 * kDeg, 1e-4);
  EXPECT_NEAR(up.roll_rad, 0.0, 1e-6);
  EXPECT_NEAR(up.cost, 15.0 / 40.0, 1e-3);
  EXPECT_NEAR(up.step_m, 0.0, 1e-5);
  EXPECT_TRUE(up.traversable);
  const PoseAssessment across = At(ground, kFlat, 0.0, 90.0);
  EXPECT_NEAR(std::abs(across.roll_rad), 15.0 * kDeg, 1e-4);
  EXPECT_NEAR(across.pitch_rad, 0.0, 1e-6);
  EXPECT_TRUE(across.traversable);
  const common::GridLayers truth =
      ComputePhysicalTruth(kMap, kWorld, ground, kFlat, RestingBody{}, GroundTruthConfig{});
  EXPECT_EQ(truth.Layer(kTraversableHeadings)(15, 15), 16.0f);
  EXPECT_NEAR(truth.Layer(layers::kTraversability)(15, 15), 15.0 / 40.0, 1e-3);
}

TEST(PhysicalTruthTest, ASlopePastTheLimitIsUntraversableAtEveryHeading) {
  const common::GridLayers truth =
      ComputePhysicalTruth(kMap, kWorld, Slope(42.0), kFlat, RestingBody{}, GroundTruthConfig{});
  EXPECT_EQ(truth.Layer(layers::kTraversability)(15, 15), 1.0f);
  EXPECT_EQ(truth.Layer(kTraversableHeadings)(15, 15), 0.0f);
  // 38 deg is within both limits
  const common::GridLayers steep =
      ComputePhysicalTruth(kMap, kWorld, Slope(38.0), kFlat, RestingBody{}, GroundTruthConfig{});
  EXPECT_EQ(steep.Layer(kTraversableHeadings)(15, 15), 16.0f);
}

// A drive along +x over a step at x = 0 (every pose 0.05 m apart over 1.2 m, centred on the edge).
bool DriveCrossesStep(double height_m) {
  const Eigen::MatrixXf ground =
      Sampled([height_m](double x, double) { return x > 0.0 ? height_m : 0.0; });
  for (double x = -0.6; x <= 0.6; x += 0.05) {
    if (!At(ground, kFlat, x, 0.0).traversable) return false;
  }
  return true;
}

TEST(PhysicalTruthTest, AStepPastTheMeasuredHeightIsNotCrossedOneBelowIs) {
  EXPECT_TRUE(DriveCrossesStep(0.10));
  EXPECT_TRUE(DriveCrossesStep(0.15));
  EXPECT_FALSE(DriveCrossesStep(0.17));
  EXPECT_FALSE(DriveCrossesStep(0.30));
  // the front wheels reach the edge (the height field's ramp from x = 0 to 0.1 m, as MuJoCo's)
  // with the robot still level: the largest step of the drive is nearly the whole height
  const Eigen::MatrixXf ground = Sampled([](double x, double) { return x > 0.0 ? 0.2 : 0.0; });
  double largest_step_m = 0.0;
  for (double x = -0.6; x <= 0.6; x += 0.01) {
    largest_step_m = std::max(largest_step_m, At(ground, kFlat, x, 0.0).step_m);
  }
  EXPECT_GT(largest_step_m, 0.18);
  EXPECT_LE(largest_step_m, 0.2);
  // parallel to the edge, on it, the robot stands with one side up: 0.2 m over the track is within
  // the roll limit, and no wheel straddles the edge
  const PoseAssessment along = At(ground, kFlat, 0.0, 90.0);
  EXPECT_NEAR(std::abs(along.roll_rad), std::atan(0.2 / 0.49), 0.03);
}

TEST(PhysicalTruthTest, ABoxTallerThanTheBellyClearanceBetweenTheWheelsIsNotTraversable) {
  auto box = [](double height_m) {
    return Sampled([height_m](double x, double y) {
      return std::abs(x) <= 0.1 && std::abs(y) <= 0.1 ? height_m : 0.0;
    });
  };
  const common::GridLayers tall =
      ComputePhysicalTruth(kMap, kWorld, kFlat, box(0.15), RestingBody{}, GroundTruthConfig{});
  EXPECT_EQ(tall.Layer(kTraversableHeadings)(15, 15), 0.0f);
  EXPECT_EQ(tall.Layer(layers::kTraversability)(15, 15), 1.0f);
  // a low one passes under the belly (0.08 of 0.115 m)
  const PoseAssessment low = At(kFlat, box(0.08), 0.0, 0.0);
  EXPECT_TRUE(low.traversable);
  EXPECT_NEAR(low.belly_m, 0.08, 1e-6);
  EXPECT_NEAR(low.cost, 0.08 / 0.115, 1e-5);
}

TEST(PhysicalTruthTest, HeadingsHalfATurnApartAgree) {
  const Eigen::MatrixXf ground = Sampled([](double x, double y) {
    return 0.1 * std::sin(3.0 * x) * std::cos(2.0 * y) + (x > 1.0 ? 0.12 : 0.0);
  });
  const common::GridLayers truth =
      ComputePhysicalTruth(kMap, kWorld, ground, kFlat, RestingBody{}, GroundTruthConfig{});
  for (int k = 0; k < 8; ++k) {
    for (const auto& [mx, my] : {std::pair{10, 12}, std::pair{18, 15}, std::pair{20, 9}}) {
      const float computed = truth.Layer(HeadingLayer(k))(mx, my);
      const RestingSurface surface{kWorld, ground, kFlat};
      const PoseAssessment back =
          AssessPose(surface, kMap.CellCenter(mx, my), M_PI + 2.0 * M_PI * k / 16.0, RestingBody{},
                     GroundTruthConfig{});
      EXPECT_NEAR(computed, back.cost, 1e-5) << "heading " << k << " cell " << mx << "," << my;
    }
  }
}

}  // namespace
}  // namespace trav::mapping
