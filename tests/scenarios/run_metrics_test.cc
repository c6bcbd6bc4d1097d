#include "scenarios/run/run_metrics.h"

#include <cmath>
#include <functional>
#include <map>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/statistics.h"

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

// Positions every 0.125 s (exact in binary), with a 15 s window sampled every 0.125 s.
TEST(LivelockMonitorTest, FiresForBackAndForthRoundOneSpotOnceTheWindowIsFull) {
  LivelockMonitor dut(15.0, 1.0);
  // a back-out of 0.6 m and the plan again, over and over: 0.6 m out and back every 2 s
  auto back_and_forth = [](int k) { return Eigen::Vector2d(0.6 * ((k / 8) % 2), 0.0); };
  for (int k = 0; k < 120; ++k) {
    ASSERT_FALSE(dut.Update(0.125 * k, back_and_forth(k))) << "t = " << 0.125 * k;
  }
  EXPECT_TRUE(dut.Update(15.0, back_and_forth(120)));
  // driving away: the window holds samples 3 m apart until it has moved past them
  EXPECT_FALSE(dut.Update(15.125, {3.0, 0.0}));
}

TEST(LivelockMonitorTest, ASlowDriveOrADetourNeverFires) {
  LivelockMonitor drive(15.0, 1.0);
  LivelockMonitor detour(15.0, 1.0);
  for (int k = 0; k <= 800; ++k) {
    const double t = 0.125 * k;
    // 0.2 m/s: 3 m per window, the ends 1.5 m from the mean
    ASSERT_FALSE(drive.Update(t, {0.2 * t, 0.0})) << "t = " << t;
    // a circle of 2 m radius driven at 0.5 m/s (a detour round an obstacle, again and again)
    ASSERT_FALSE(detour.Update(t, 2.0 * Eigen::Vector2d(std::cos(0.25 * t), std::sin(0.25 * t))))
        << "t = " << t;
  }
}

TEST(LivelockMonitorTest, TimeWithAMoverNearDoesNotCount) {
  LivelockMonitor dut(15.0, 1.0);
  auto back_and_forth = [](int k) { return Eigen::Vector2d(0.6 * ((k / 8) % 2), 0.0); };
  // a walker 2.9 m away for the first 10 s (giving way to it, back and forth), then 3.1 m
  for (int k = 0; k <= 80; ++k) {
    ASSERT_FALSE(dut.Update(0.125 * k, back_and_forth(k), {{0.0, 2.9}}));
  }
  // the window starts at 10.125 s, when the walker is no longer near
  for (int k = 81; k < 201; ++k) {
    ASSERT_FALSE(dut.Update(0.125 * k, back_and_forth(k), {{0.0, 3.1}})) << "t = " << 0.125 * k;
  }
  EXPECT_TRUE(dut.Update(25.125, back_and_forth(201), {{0.0, 3.1}}));
}

TEST(LivelockMonitorTest, AZeroWindowTurnsItOff) {
  LivelockMonitor dut(0.0, 1.0);
  for (int k = 0; k <= 800; ++k) ASSERT_FALSE(dut.Update(0.125 * k, {0.0, 0.0}));
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
  const std::map<std::string, ModuleTime> times = dut.Summary();
  ASSERT_EQ(times.size(), 1u);
  const ModuleTime& planning = times.at("planning");
  EXPECT_EQ(planning.calls, 3);
  EXPECT_DOUBLE_EQ(planning.median_ms, 2.0);
  EXPECT_DOUBLE_EQ(planning.max_ms, 3.0);
  EXPECT_DOUBLE_EQ(planning.total_s, 0.006);
  EXPECT_EQ(nlohmann::json(planning).dump(),
            R"({"calls":3,"max_ms":3.0,"median_ms":2.0,"total_s":0.006})");
  EXPECT_DOUBLE_EQ(dut.Total("planning"), 6.0);
  EXPECT_DOUBLE_EQ(dut.Total("mapping"), 0.0);
}

TEST(QuantileTest, TakesTheElementAtTheFlooredRank) {
  EXPECT_DOUBLE_EQ(common::Quantile({}, 0.5), 0.0);
  EXPECT_DOUBLE_EQ(common::Quantile({5.0, 1.0, 3.0}, 0.5), 3.0);
  EXPECT_DOUBLE_EQ(common::Quantile({4.0, 1.0, 3.0, 2.0}, 0.5), 2.0);  // rank floor(1.5) = 1
  EXPECT_DOUBLE_EQ(common::Quantile({4.0, 1.0, 3.0, 2.0}, 1.0), 4.0);
  EXPECT_DOUBLE_EQ(common::Quantile({4.0, 1.0, 3.0, 2.0}, 0.0), 1.0);
}

// A 1 m grid of 11 x 11 cells centred on the origin, and an area with a 4 m window.
common::GridGeometry UnitGrid() {
  return common::GridGeometry::Centered({0.0, 0.0}, {10.0, 10.0}, 1.0);
}
mapping::MapArea SmallWindow() {
  mapping::MapArea area;
  area.window_m = 4.0;
  area.resolution_m = 1.0;
  area.map_size_m = 10.0;
  area.max_height_above_robot_m = 1.0;
  return area;
}

TEST(ObservedCellsTest, CountsEachCellOnceInTheWindowAndBelowTheHeightLimit) {
  ObservedCells observed(UnitGrid(), SmallWindow());
  const common::PointCloud frame = common::MakePointCloud({
      {0.1f, 0.2f, 0.0f},   // cell (5, 5)
      {-0.2f, 0.1f, 0.0f},  // cell (5, 5) again
      {1.0f, 1.9f, 0.5f},   // cell (6, 7)
      {3.0f, 0.0f, 0.0f},   // outside the 4 m window
      {1.0f, 0.0f, 1.5f},   // higher than 1 m above the base
      {NAN, 0.0f, 0.0f},    // invalid
  });
  EXPECT_EQ(observed.Add(frame, {0.0, 0.0, 0.0}), 2);
  ASSERT_EQ(observed.cells().size(), 2u);
  EXPECT_EQ(observed.cells()[0], Eigen::Vector2i(5, 5));
  EXPECT_EQ(observed.cells()[1], Eigen::Vector2i(6, 7));
  // the same points from a base moved 2 m along x: (3, 0) now lies in the window
  EXPECT_EQ(observed.Add(frame, {2.0, 0.0, 0.0}), 1);
  EXPECT_EQ(observed.cells().back(), Eigen::Vector2i(8, 5));
}

// Four observed cells: two hazards (truth 0.9 and 1.0) and two free cells (0.1, 0.3), ground at
// 0.5 m.
struct HazardWorld {
  HazardWorld()
      : truth(UnitGrid(), {"traversability", "elevation"}), observed(UnitGrid(), SmallWindow()) {
    truth.Layer("traversability").setConstant(0.0f);
    truth.Layer("elevation").setConstant(0.5f);
    truth.Layer("traversability")(5, 5) = 0.9f;
    truth.Layer("traversability")(6, 5) = 0.1f;
    truth.Layer("traversability")(4, 6) = 1.0f;
    truth.Layer("traversability")(5, 6) = 0.3f;
    observed.Add(
        common::MakePointCloud(
            {{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {-1.0f, 1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}}),
        {0.0, 0.0, 0.0});
  }
  common::GridLayers truth;
  ObservedCells observed;
};

TEST(ScoreHazardsTest, TheOracleRanksEveryHazardFirstAndAConstantCannotRank) {
  const HazardWorld world;
  const HazardScores oracle = ScoreHazards(world.truth, world.truth, world.observed, 0.8);
  EXPECT_EQ(oracle.compared_cells, 4);
  EXPECT_EQ(oracle.hazard_cells, 2);
  EXPECT_EQ(oracle.auroc, 1.0);
  EXPECT_EQ(oracle.average_precision, 1.0);
  EXPECT_EQ(oracle.spearman, 1.0);
  EXPECT_EQ(oracle.elevation_rmse_m, 0.0);
  // (cost bin, truth bin, count) in bin order: 0.1, 0.3, 0.9, 1.0 in steps of 0.01
  EXPECT_EQ(
      oracle.cost_truth_histogram,
      (std::vector<std::array<int, 3>>{{10, 10, 1}, {30, 30, 1}, {90, 90, 1}, {100, 100, 1}}));

  common::GridLayers constant(UnitGrid(), {"traversability"});
  constant.Layer("traversability").setConstant(0.4f);
  const HazardScores flat = ScoreHazards(constant, world.truth, world.observed, 0.8);
  EXPECT_EQ(flat.auroc, 0.5);
  EXPECT_EQ(flat.average_precision, 0.5);           // the share of hazards
  EXPECT_FALSE(flat.spearman.has_value());          // no spread
  EXPECT_FALSE(flat.elevation_rmse_m.has_value());  // no elevation layer
}

TEST(ScoreHazardsTest, AMapThatSwapsAHazardWithAFreeCellLosesRankAndHeightErrorsCount) {
  const HazardWorld world;
  common::GridLayers map = world.truth;
  map.Layer("traversability")(5, 5) = 0.2f;  // a hazard mapped as free ground
  map.Layer("elevation")(5, 5) = 0.9f;       // 0.4 m off
  const HazardScores scores = ScoreHazards(map, world.truth, world.observed, 0.8);
  // hazards 0.2 and 1.0 against free 0.1 and 0.3: pairs won 1 + 2 of 4
  EXPECT_EQ(scores.auroc, 0.75);
  // 1.0 first (precision 1), then 0.3 (free), then 0.2: precision 2/3
  EXPECT_DOUBLE_EQ(*scores.average_precision, (1.0 + 2.0 / 3.0) / 2.0);
  EXPECT_NEAR(*scores.elevation_rmse_m, std::sqrt(0.16 / 4.0), 1e-6);
  // unknown cells of the map are not scored
  map.Layer("traversability")(4, 6) = NAN;
  EXPECT_EQ(ScoreHazards(map, world.truth, world.observed, 0.8).compared_cells, 3);
}

TEST(CompareObservedTest, ScoresObservedCellsTheMapKnows) {
  const common::GridGeometry geometry = UnitGrid();
  common::GridLayers truth(geometry, {"traversability"});
  for (int ix = 0; ix < geometry.num_x; ++ix) {
    for (int iy = 0; iy < geometry.num_y; ++iy) {
      truth.Layer("traversability")(ix, iy) = 0.1f * static_cast<float>(ix % 3);
    }
  }
  ObservedCells observed(geometry, SmallWindow());
  observed.Add(common::MakePointCloud({{0.0f, 0.0f, 0.0f},     // (5, 5): truth 0.2
                                       {1.0f, 0.0f, 0.0f},     // (6, 5): truth 0.0
                                       {-1.0f, 1.0f, 0.0f}}),  // (4, 6): truth 0.1
               {0.0, 0.0, 0.0});

  // the oracle scores zero; a constant scores its distance to the truth
  EXPECT_EQ(CompareObserved(truth, truth, observed, "traversability").mean, 0.0);
  common::GridLayers constant(geometry, {"traversability"});
  constant.Layer("traversability").setConstant(0.3f);
  const LayerError error = CompareObserved(constant, truth, observed, "traversability");
  ASSERT_EQ(error.known_cells, 3);
  EXPECT_NEAR(error.mean, (0.1 + 0.3 + 0.2) / 3.0, 1e-6);
  EXPECT_NEAR(error.variance, (0.01 + 0.09 + 0.04) / 3.0 - 0.04, 1e-6);
  // the cells observed first only (those of the frames up to one)
  const LayerError first_two = CompareObserved(constant, truth, observed, "traversability", 2);
  ASSERT_EQ(first_two.known_cells, 2);
  EXPECT_NEAR(first_two.mean, (0.1 + 0.3) / 2.0, 1e-6);
  EXPECT_EQ(CompareObserved(constant, truth, observed, "traversability", 7).known_cells, 3);

  // unknown cells of the map are not scored; unobserved cells never are
  constant.Layer("traversability")(6, 5) = NAN;
  EXPECT_EQ(CompareObserved(constant, truth, observed, "traversability").known_cells, 2);
  // a map on another grid is looked up at each observed cell's centre
  common::GridLayers shifted(common::GridGeometry::Centered({0.25, 0.0}, {4.0, 4.0}, 1.0),
                             {"traversability"});
  shifted.Layer("traversability").setConstant(0.2f);
  const LayerError on_shifted = CompareObserved(shifted, truth, observed, "traversability");
  EXPECT_EQ(on_shifted.known_cells, 3);
  EXPECT_NEAR(on_shifted.mean, (0.0 + 0.2 + 0.1) / 3.0, 1e-6);
  // the same with the map's cells looked up beforehand: cell (5, 5)'s centre (0, 0) in the shifted
  // map's cell (2, 2) of 5 x 5 (origin (-1.75, -2)), (6, 5)'s in (3, 2), (4, 6)'s in (1, 3); none
  // in a map off to the side
  const std::vector<int> map_cells = MapCellIndices(shifted.geometry(), observed, 3);
  EXPECT_EQ(map_cells, (std::vector<int>{2 + 2 * 5, 3 + 2 * 5, 1 + 3 * 5}));
  const LayerError looked_up = CompareObserved(shifted.Layer("traversability"),
                                               truth.Layer("traversability"), observed, map_cells);
  EXPECT_EQ(looked_up.known_cells, on_shifted.known_cells);
  EXPECT_EQ(looked_up.mean, on_shifted.mean);
  EXPECT_EQ(looked_up.variance, on_shifted.variance);
  const common::GridGeometry aside = common::GridGeometry::Centered({10.0, 0.0}, {4.0, 4.0}, 1.0);
  EXPECT_EQ(MapCellIndices(aside, observed, 2), (std::vector<int>{-1, -1}));
}

}  // namespace
}  // namespace trav::scenarios

namespace trav::scenarios {
namespace {

// A straight drive along x, sampled every 0.1 m for `length_m`, the estimate `estimated(X_WB)`.
std::vector<PoseSample> StraightDrive(
    double length_m, const std::function<Eigen::Isometry3d(const Eigen::Isometry3d&)>& estimated) {
  std::vector<PoseSample> samples;
  for (int k = 0; k * 0.1 <= length_m + 1e-9; ++k) {
    PoseSample sample;
    sample.distance_m = 0.1 * k;
    sample.X_WB.translation().x() = 0.1 * k;
    sample.X_OB = estimated(sample.X_WB);
    samples.push_back(sample);
  }
  return samples;
}

TEST(RelativePoseErrorTest, AScaleErrorShowsAsItsShareOfTheStretch) {
  // the odometry reads 1 % too far: 0.1 m over every 10 m
  const RelativePoseError dut =
      RelativePoseErrorOver(StraightDrive(20.0,
                                          [](const Eigen::Isometry3d& X_WB) {
                                            Eigen::Isometry3d X_OB = X_WB;
                                            X_OB.translation() *= 1.01;
                                            return X_OB;
                                          }),
                            10.0);
  EXPECT_GE(dut.stretches, 100);
  EXPECT_NEAR(dut.translation_m, 0.1, 1e-3);
  EXPECT_NEAR(dut.yaw_deg, 0.0, 1e-9);
}

TEST(RelativePoseErrorTest, AConstantOffsetIsNoRelativeError) {
  // a frame O turned and shifted from W once and for all: every motion is right
  Eigen::Isometry3d X_OW = Eigen::Isometry3d::Identity();
  X_OW.linear() = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  X_OW.translation() = Eigen::Vector3d(0.5, -0.3, 0.1);
  const RelativePoseError dut = RelativePoseErrorOver(
      StraightDrive(15.0, [&](const Eigen::Isometry3d& X_WB) { return X_OW * X_WB; }), 10.0);
  EXPECT_GT(dut.stretches, 40);
  EXPECT_NEAR(dut.translation_m, 0.0, 1e-9);
  EXPECT_NEAR(dut.yaw_deg, 0.0, 1e-9);
}

TEST(RelativePoseErrorTest, ShorterDrivesHaveNoStretch) {
  const RelativePoseError dut = RelativePoseErrorOver(
      StraightDrive(9.5, [](const Eigen::Isometry3d& X_WB) { return X_WB; }), 10.0);
  EXPECT_EQ(dut.stretches, 0);
  EXPECT_EQ(dut.translation_m, 0.0);
}

}  // namespace
}  // namespace trav::scenarios
