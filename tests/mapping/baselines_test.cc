#include "mapping/baselines.h"

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

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
  ElevationMapConfig config;
  config.area.ground_crop = false;  // its own handling of obstacles: the higher point wins
  ElevationMapper dut(config, FsgpConfig{});
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

// A 0.6 m crate at (2, 2): with the ground crop and the obstacle layer FSGP-BGK has, each baseline
// marks its faces untraversable; without them the obstacle layer stays unknown.
TEST(BaselinesTest, EveryBaselineGetsTheSharedGroundCropAndObstacleLayer) {
  const auto crate = [](double x, double y) {
    return std::abs(x - 2) < 0.5 && std::abs(y - 2) < 0.5 ? 0.6 : 0.0;
  };
  for (const bool shared : {true, false}) {
    MapArea area;
    area.ground_crop = shared;
    area.obstacle_layer = shared;
    SgpConfig sgp;
    sgp.area = area;
    ElevationMapConfig em;
    em.area = area;
    std::unique_ptr<TraversabilityMapper> mappers[] = {
        std::make_unique<SgpMapper>(sgp), std::make_unique<ElevationMapper>(em, FsgpConfig{})};
    for (const std::unique_ptr<TraversabilityMapper>& dut : mappers) {
      ASSERT_EQ(dut->Update(Surface(crate, {0, 0}), RobotAt(0, 0), 0.0).status,
                MapUpdateStatus::kUpdated);
      const std::optional<float> face = dut->map().At(layers::kObstacle, {1.5, 2.0});
      if (shared) {
        EXPECT_EQ(face, 1.0f);
        EXPECT_EQ(dut->map().At(layers::kTraversability, {1.5, 2.0}), 1.0f);
        EXPECT_EQ(dut->map().At(layers::kObstacle, {-2.0, -2.0}), 0.0f);  // open ground
      } else {
        EXPECT_FALSE(face.has_value());
      }
    }
  }
}

// SGP predicts exactly the cells with an inducing point within its support radius (0.8 m): with
// fewer points than M every point is one. Its variance layer is known wherever the elevation is,
// shared by each 4 x 4 block of cells from its corner (variance_stride).
TEST(BaselinesTest, SgpPredictsOnlyNearItsInducingPointsWithAStridedVariance) {
  // flat ground on a 0.5 m lattice with a 3 m hole around (2.5, 2.5)
  std::vector<Eigen::Vector3f> points;
  for (int i = -10; i <= 10; ++i) {
    for (int j = -10; j <= 10; ++j) {
      const Eigen::Vector3f p(0.5f * i, 0.5f * j, 0.0f);
      if (std::abs(p.x() - 2.5f) > 1.5f || std::abs(p.y() - 2.5f) > 1.5f) points.push_back(p);
    }
  }
  const SgpConfig config;
  ASSERT_LT(static_cast<int>(points.size()), config.inducing_points);
  SgpMapper dut{config};
  ASSERT_EQ(dut.Update(common::MakePointCloud(points), RobotAt(0, 0), 0.0).status,
            MapUpdateStatus::kUpdated);
  const common::GridLayers& map = dut.map();
  const common::GridGeometry& g = map.geometry();
  int known = 0, unknown = 0;
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      const Eigen::Vector2d c = g.CellCenter(ix, iy);
      if (c.cwiseAbs().maxCoeff() > 4.5) continue;  // the window
      double nearest = std::numeric_limits<double>::infinity();
      for (const Eigen::Vector3f& p : points) {
        nearest = std::min(nearest, (p.head<2>().cast<double>() - c).norm());
      }
      if (std::abs(nearest - config.support_radius_m) < 1e-3) continue;  // a tie
      const bool elevation = !std::isnan(map.Layer(layers::kElevation)(ix, iy));
      EXPECT_EQ(elevation, nearest < config.support_radius_m) << c.transpose();
      const float variance = map.Layer(layers::kElevationVariance)(ix, iy);
      EXPECT_EQ(elevation, !std::isnan(variance)) << c.transpose();
      ++(elevation ? known : unknown);
      if (!elevation) continue;
      EXPECT_GT(variance, 0.0f);
      const int cx = ix - ix % 4, cy = iy - iy % 4;
      if (!std::isnan(map.Layer(layers::kElevation)(cx, cy))) {
        EXPECT_EQ(variance, map.Layer(layers::kElevationVariance)(cx, cy)) << c.transpose();
      }
    }
  }
  EXPECT_GT(known, 1000);
  EXPECT_GT(unknown, 10);  // the middle of the hole
}

}  // namespace
}  // namespace trav::mapping
