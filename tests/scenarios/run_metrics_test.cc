#include "scenarios/run_metrics.h"

#include <cmath>

#include <gtest/gtest.h>

namespace trav::scenarios {
namespace {

TEST(BarnScoreTest, FollowsTheChallengesClippedRatio) {
  // OT / clip(AT, 2 OT, 8 OT)
  EXPECT_DOUBLE_EQ(BarnScore(true, 5.0, 10.0), 0.5);  // faster than 2 OT: capped
  EXPECT_DOUBLE_EQ(BarnScore(true, 40.0, 10.0), 0.25);
  EXPECT_DOUBLE_EQ(BarnScore(true, 200.0, 10.0), 0.125);  // slower than 8 OT: floor
  EXPECT_DOUBLE_EQ(BarnScore(false, 40.0, 10.0), 0.0);
  EXPECT_DOUBLE_EQ(BarnScore(true, 40.0, 0.0), 0.0);
}

TEST(ProgressMonitorTest, StuckOnlyAfterStayingInOnePlaceForTheWindow) {
  ProgressMonitor dut(10.0, 0.3);
  EXPECT_FALSE(dut.Update(0.0, {0.0, 0.0}));
  EXPECT_FALSE(dut.Update(9.9, {0.2, 0.0}));  // within 0.3 m of where it was at t = 0
  EXPECT_TRUE(dut.Update(10.1, {0.25, 0.0}));
  EXPECT_FALSE(dut.Update(10.2, {0.5, 0.0}));  // moved on: a new anchor
  EXPECT_FALSE(dut.Update(20.1, {0.6, 0.0}));
  EXPECT_TRUE(dut.Update(20.3, {0.6, 0.0}));
}

TEST(CompareLayersTest, MeanAndVarianceOverCellsKnownInBoth) {
  Eigen::MatrixXf predicted(2, 2), truth(2, 2);
  predicted << 0.1f, 0.5f, NAN, 0.9f;
  truth << 0.3f, 0.5f, 0.2f, 0.5f;
  const LayerError error = CompareLayers(predicted, truth);
  ASSERT_EQ(error.known_cells, 3);
  // errors 0.2, 0.0, 0.4
  EXPECT_NEAR(error.mean, 0.2, 1e-6);
  EXPECT_NEAR(error.variance, (0.04 + 0.0 + 0.16) / 3.0 - 0.04, 1e-6);
}

TEST(CompareWithTruthTest, LooksTheTruthUpAtEachKnownCellCentre) {
  // the map: 1 m cells around (10, 10); the truth: 0.5 m cells over a larger area
  common::GridLayers map(common::GridGeometry::Centered({10, 10}, {2, 2}, 1.0), {"t"});
  map.Layer("t").setConstant(0.5f);
  map.Layer("t")(0, 0) = NAN;
  common::GridLayers truth(common::GridGeometry::Centered({10, 10}, {10, 10}, 0.5), {"t"});
  const common::GridGeometry& g = truth.geometry();
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      truth.Layer("t")(ix, iy) = g.CellCenter(ix, iy).x() >= 10.0 ? 1.0f : 0.0f;
    }
  }
  const LayerError error = CompareWithTruth(map, truth, "t");
  EXPECT_EQ(error.known_cells, 8);
  EXPECT_NEAR(error.mean, 0.5, 1e-6);
  EXPECT_NEAR(error.variance, 0.0, 1e-6);
}

TEST(ModuleTimesTest, ReportsCallsMedianMaximumAndTotal) {
  ModuleTimes dut;
  for (double ms : {3.0, 1.0, 2.0}) dut.Add("planning", ms);
  const nlohmann::json json = dut.ToJson();
  EXPECT_EQ(json["planning"]["calls"], 3);
  EXPECT_DOUBLE_EQ(json["planning"]["median_ms"], 2.0);
  EXPECT_DOUBLE_EQ(json["planning"]["max_ms"], 3.0);
  EXPECT_DOUBLE_EQ(json["planning"]["total_s"], 0.006);
  EXPECT_DOUBLE_EQ(dut.Total("planning"), 6.0);
  EXPECT_DOUBLE_EQ(dut.Total("mapping"), 0.0);
}

}  // namespace
}  // namespace trav::scenarios
