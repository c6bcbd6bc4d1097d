#include "mapping/ground_truth.h"

#include <cmath>

#include <gtest/gtest.h>

#include "mapping/traversability_mapper.h"
#include "tests/mapping/sampled_grid.h"

namespace trav::mapping {
namespace {

const common::GridGeometry kWorld =
    common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(10, 10), 0.1);
const common::GridGeometry kMap =
    common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(8, 8), 0.2);

Eigen::MatrixXf Heights(double (*height)(double, double)) {
  return test_util::Sampled(kWorld, height);
}

const Eigen::MatrixXf kNoObstacles = Eigen::MatrixXf::Zero(101, 101);

TEST(GroundTruthTest, FlatGroundIsZeroEverywhere) {
  const common::GridLayers truth =
      ComputeGroundTruth(kMap, kWorld, Heights([](double, double) { return 0.4; }), kNoObstacles,
                         FsgpConfig{}, GroundTruthConfig{});
  const Eigen::MatrixXf& t = truth.Layer(layers::kTraversability);
  EXPECT_FALSE(t.array().isNaN().any());
  EXPECT_LT(t.cwiseAbs().maxCoeff(), 1e-6f);
}

TEST(GroundTruthTest, AThirtyDegreeSlopeSaturatesTheSlopeTerm) {
  const FsgpConfig score;
  const common::GridLayers truth = ComputeGroundTruth(
      kMap, kWorld, Heights([](double x, double) { return std::tan(M_PI / 6) * x; }), kNoObstacles,
      score, GroundTruthConfig{});
  // an interior cell: the slope is 30 deg, the plane has no curvature; the gradient term is the
  // mean height difference to the centre over the 0.3 m disc
  const float slope = *truth.At(layers::kSlope, {0.0, 0.0});
  EXPECT_NEAR(slope, M_PI / 6, 1e-4);
  EXPECT_LT(*truth.At(layers::kCurvature, {0.0, 0.0}), 1e-4);
  const double gradient = *truth.At(layers::kGradient, {0.0, 0.0});
  EXPECT_NEAR(*truth.At(layers::kTraversability, {0.0, 0.0}),
              score.weight_slope * 1.0 +
                  score.weight_gradient * std::min(1.0, gradient / score.gradient_max_m),
              1e-5);
}

TEST(GroundTruthTest, CellsOfATwentyCentimetreBoxAreUntraversableAndTheFootprintRadiusGrowsThem) {
  // a 0.6 m x 0.6 m box 0.2 m high at (2, 2)
  Eigen::MatrixXf obstacles = kNoObstacles;
  for (int ix = 0; ix < kWorld.num_x; ++ix) {
    for (int iy = 0; iy < kWorld.num_y; ++iy) {
      const Eigen::Vector2d p = kWorld.CellCenter(ix, iy);
      if (std::abs(p.x() - 2.0) <= 0.3 && std::abs(p.y() - 2.0) <= 0.3) obstacles(ix, iy) = 0.2f;
    }
  }
  const common::GridLayers truth =
      ComputeGroundTruth(kMap, kWorld, Heights([](double, double) { return 0.0; }), obstacles,
                         FsgpConfig{}, GroundTruthConfig{});
  EXPECT_EQ(*truth.At(layers::kTraversability, {2.0, 2.0}), 1.0f);
  EXPECT_EQ(*truth.At(layers::kTraversability, {2.2, 2.0}), 1.0f);  // the box's edge cell
  // by default the box's own cells only: the planners add the robot's footprint
  EXPECT_LT(*truth.At(layers::kTraversability, {2.4, 2.0}), 1.0f);
  GroundTruthConfig grown;
  grown.footprint_radius_m = 0.3;
  const common::GridLayers truth_grown = ComputeGroundTruth(
      kMap, kWorld, Heights([](double, double) { return 0.0; }), obstacles, FsgpConfig{}, grown);
  EXPECT_EQ(*truth_grown.At(layers::kTraversability, {2.4, 2.0}), 1.0f);  // within 0.3 m of it
  EXPECT_EQ(*truth_grown.At(layers::kTraversability, {1.6, 2.0}), 1.0f);
  EXPECT_EQ(*truth.At(layers::kTraversability, {-2.0, -2.0}), 0.0f);
  EXPECT_LT(*truth.At(layers::kTraversability, {3.4, 2.0}), 1.0f);
}

}  // namespace
}  // namespace trav::mapping
