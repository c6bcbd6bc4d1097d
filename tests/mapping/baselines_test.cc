#include "mapping/baselines.h"

#include <memory>

#include <gtest/gtest.h>

#include "tests/mapping/mapping_test_util.h"

namespace trav::mapping {
namespace {

using testing::MeanNear;
using testing::RobotAt;
using testing::Surface;

constexpr double kDegToRad = M_PI / 180.0;

TEST(BaselinesTest, FlatGroundIsEasyAndATwentyDegreePlaneHasItsSlope) {
  const double gradient = std::tan(20.0 * kDegToRad);
  for (int kind = 0; kind < 2; ++kind) {
    for (bool tilted : {false, true}) {
      std::unique_ptr<TraversabilityMapper> dut;
      if (kind == 0) dut = std::make_unique<SgpMapper>(SgpConfig{});
      if (kind == 1) dut = std::make_unique<ElevationMapper>(ElevationMapConfig{}, FsgpConfig{});
      const MapUpdateResult result = dut->Update(
          Surface([&](double x, double) { return tilted ? gradient * x : 0.0; }, {0, 0}),
          RobotAt(0, 0), 0.0);
      ASSERT_EQ(result.status, MapUpdateStatus::kUpdated);
      const double slope = MeanNear(dut->map(), layers::kSlope, {0, 0}, 3.0);
      if (tilted) {
        EXPECT_NEAR(slope, 20.0 * kDegToRad, 1.0 * kDegToRad) << "mapper " << kind;
      } else {
        EXPECT_LT(slope, 1.0 * kDegToRad) << "mapper " << kind;
        EXPECT_LT(MeanNear(dut->map(), layers::kTraversability, {0, 0}, 3.0), 0.03)
            << "mapper " << kind;
      }
    }
  }
}

TEST(BaselinesTest, ElevationMapFusesRepeatedHeightsAndTakesNewObstacles) {
  ElevationMapper dut(ElevationMapConfig{}, FsgpConfig{});
  dut.Update(Surface([](double, double) { return 0.0; }, {0, 0}), RobotAt(0, 0), 0.0);
  const float variance_once = *dut.map().At(layers::kElevationVariance, {1.0, 1.0});
  dut.Update(Surface([](double, double) { return 0.0; }, {0, 0}), RobotAt(0, 0), 1.0);
  EXPECT_LT(*dut.map().At(layers::kElevationVariance, {1.0, 1.0}), variance_once);
  // a 0.3 m block appears at (2, 2): the cells jump to its top
  dut.Update(
      Surface([](double x,
                 double y) { return std::abs(x - 2) < 0.5 && std::abs(y - 2) < 0.5 ? 0.3 : 0.0; },
              {0, 0}),
      RobotAt(0, 0), 2.0);
  EXPECT_NEAR(*dut.map().At(layers::kElevation, {2.0, 2.0}), 0.3, 0.01);
  EXPECT_GT(*dut.map().At(layers::kTraversability, {2.5, 2.0}), 0.3);
}

}  // namespace
}  // namespace trav::mapping
