#include "sim/noise.h"

#include <gtest/gtest.h>

namespace trav::sim {
namespace {

TEST(PerlinNoiseTest, IsZeroOnLatticePoints) {
  const PerlinNoise dut(3);
  for (int x = -3; x <= 3; ++x) {
    for (int y = -3; y <= 3; ++y) EXPECT_DOUBLE_EQ(dut.Sample(Eigen::Vector2d(x, y)).value, 0.0);
  }
}

TEST(PerlinNoiseTest, GradientMatchesCentralDifferences) {
  const PerlinNoise dut(11);
  const double h = 1e-6;
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(0.3, 0.7), Eigen::Vector2d(-4.2, 1.9),
                                   Eigen::Vector2d(17.55, -3.01), Eigen::Vector2d(0.5, 0.5)}) {
    const NoiseSample sample = dut.Sample(p);
    const double dx = (dut.Sample(p + Eigen::Vector2d(h, 0)).value -
                       dut.Sample(p - Eigen::Vector2d(h, 0)).value) /
                      (2 * h);
    const double dy = (dut.Sample(p + Eigen::Vector2d(0, h)).value -
                       dut.Sample(p - Eigen::Vector2d(0, h)).value) /
                      (2 * h);
    EXPECT_NEAR(sample.gradient.x(), dx, 1e-6) << "at " << p.transpose();
    EXPECT_NEAR(sample.gradient.y(), dy, 1e-6) << "at " << p.transpose();
  }
}

TEST(PerlinNoiseTest, SeedsAreReproducibleAndDistinct) {
  const Eigen::Vector2d p(2.37, -1.61);
  EXPECT_EQ(PerlinNoise(5).Sample(p).value, PerlinNoise(5).Sample(p).value);
  EXPECT_NE(PerlinNoise(5).Sample(p).value, PerlinNoise(6).Sample(p).value);
}

TEST(FractalNoiseTest, FamiliesDifferAndRidgedIsBoundedByOctaveSum) {
  FractalParams params;
  params.octaves = 3;
  params.gain = 0.5;
  const Eigen::Vector2d p(1.3, 2.1);
  double values[4];
  int k = 0;
  for (FractalFamily family : {FractalFamily::kFbm, FractalFamily::kRidged, FractalFamily::kBillowy,
                               FractalFamily::kSwiss}) {
    params.family = family;
    values[k++] = FractalNoise(9, params).Evaluate(p);
  }
  EXPECT_NE(values[0], values[1]);
  EXPECT_NE(values[1], values[2]);
  EXPECT_NE(values[1], values[3]);
  // ridged and billowy octaves lie in [0, 1]: the sum in [0, 1 + 0.5 + 0.25]
  EXPECT_GE(values[1], 0.0);
  EXPECT_LE(values[1], 1.75);
  EXPECT_GE(values[2], 0.0);
  EXPECT_LE(values[2], 1.75);
}

}  // namespace
}  // namespace trav::sim
