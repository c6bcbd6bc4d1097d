#include "planner/cost_field.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "common/random.h"

namespace trav::planner {
namespace {

using Mask = Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>;

TEST(DistanceTransformTest, EqualsBruteForceOnARandomMask) {
  common::Random random(7);
  Mask mask(23, 17);
  for (int ix = 0; ix < 23; ++ix) {
    for (int iy = 0; iy < 17; ++iy) mask(ix, iy) = random.Bernoulli(0.05);
  }
  const Eigen::MatrixXd dut = DistanceTransform(mask);
  for (int ix = 0; ix < 23; ++ix) {
    for (int iy = 0; iy < 17; ++iy) {
      double best = std::numeric_limits<double>::infinity();
      for (int jx = 0; jx < 23; ++jx) {
        for (int jy = 0; jy < 17; ++jy) {
          if (mask(jx, jy)) best = std::min(best, std::hypot(ix - jx, iy - jy));
        }
      }
      EXPECT_DOUBLE_EQ(dut(ix, iy), best) << ix << "," << iy;
    }
  }
}

TEST(DistanceTransformTest, IsInfiniteWithoutSites) {
  const Eigen::MatrixXd dut = DistanceTransform(Mask::Constant(4, 5, false));
  EXPECT_TRUE(std::isinf(dut(2, 3)));
}

// 4 x 4 m at 0.1 m; lethal cells at x >= 1 (a wall), cost 0.2 elsewhere, one unknown cell.
common::GridLayers WallMap() {
  common::GridLayers map(
      common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(4, 4), 0.1),
      {"traversability"});
  const common::GridGeometry& g = map.geometry();
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      map.Layer("traversability")(ix, iy) = g.CellCenter(ix, iy).x() >= 0.95 ? 1.0f : 0.2f;
    }
  }
  return map;
}

TEST(CostFieldTest, SignedDistanceCrossesZeroOnTheLethalBoundary) {
  const CostField dut(WallMap(), CostMapConfig{});
  // the boundary between the last free (x = 0.9) and first lethal (x = 1.0) cell centres
  EXPECT_NEAR(dut.Distance({0.95, 0.3}).value, 0.0, 1e-12);
  EXPECT_NEAR(dut.Distance({0.0, 0.3}).value, 0.95, 1e-12);
  EXPECT_NEAR(dut.Distance({-0.52, 0.3}).value, 1.47, 1e-12);
  EXPECT_NEAR(dut.Distance({1.3, 0.3}).value, -0.35, 1e-12);
  const FieldSample s = dut.Distance({0.03, 0.31});
  EXPECT_NEAR(s.gradient_W.x(), -1.0, 1e-12);
  EXPECT_NEAR(s.gradient_W.y(), 0.0, 1e-12);
}

TEST(CostFieldTest, CostIsBilinearWithItsGradient) {
  common::GridLayers map = WallMap();
  const common::GridGeometry& g = map.geometry();
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      const Eigen::Vector2d p = g.CellCenter(ix, iy);
      map.Layer("traversability")(ix, iy) = static_cast<float>(0.25 + 0.1 * p.x() + 0.05 * p.y());
    }
  }
  const CostField dut(map, CostMapConfig{});
  // a plane is reproduced exactly by bilinear interpolation
  const FieldSample s = dut.Cost({0.123, -0.456});
  EXPECT_NEAR(s.value, 0.25 + 0.1 * 0.123 - 0.05 * 0.456, 1e-6);
  EXPECT_NEAR(s.gradient_W.x(), 0.1, 1e-5);
  EXPECT_NEAR(s.gradient_W.y(), 0.05, 1e-5);
  // beyond the border: the border value, no gradient
  const FieldSample outside = dut.Cost({5.0, 0.0});
  EXPECT_NEAR(outside.value, 0.25 + 0.2, 1e-6);
  EXPECT_EQ(outside.gradient_W.x(), 0.0);
}

TEST(CostFieldTest, UnknownCellsFollowThePolicy) {
  common::GridLayers map = WallMap();
  map.Layer("traversability")(5, 20) = std::numeric_limits<float>::quiet_NaN();
  const Eigen::Vector2d unknown_W = map.geometry().CellCenter(5, 20);
  CostMapConfig config;
  config.unknown_cost = 0.7;
  EXPECT_NEAR(CostField(map, config).Cost(unknown_W).value, 0.7, 1e-12);
  EXPECT_GT(CostField(map, config).Distance(unknown_W).value, 0.0);
  config.unknown_policy = UnknownPolicy::kBlocked;
  EXPECT_NEAR(CostField(map, config).Distance(unknown_W).value, -0.05, 1e-12);
}

TEST(CostFieldTest, AMapWithoutLethalCellsIsFarEverywhere) {
  common::GridLayers map = WallMap();
  map.Layer("traversability").setConstant(0.1f);
  EXPECT_EQ(CostField(map, CostMapConfig{}).Distance({0.0, 0.0}).value, CostField::kFarDistance);
}

TEST(CostFieldTest, TheSpeedLimitFollowsUnknownCellsAndRoughnessWithinReach) {
  // 4 x 4 m at 0.1 m: one unknown cell, one cell of roughness 0.03 and one of 0.02
  common::GridLayers map = WallMap();
  map.Layer("traversability").setConstant(0.1f);
  map.AddLayer("roughness");
  const common::GridGeometry& g = map.geometry();
  map.Layer("traversability")(5, 5) = std::numeric_limits<float>::quiet_NaN();
  map.Layer("roughness")(30, 30) = 0.03f;
  map.Layer("roughness")(10, 30) = 0.02f;
  CostMapConfig config;
  config.speed.open_m_s = 1.5;
  config.speed.unknown_m_s = 0.8;
  config.speed.rough_m_s = 1.1;
  config.speed.smooth_m = 0.01;
  config.speed.rough_m = 0.03;
  const CostField dut(map, config);
  EXPECT_NEAR(dut.open_speed_m_s(), 1.5, 1e-6);
  EXPECT_NEAR(dut.SpeedLimit(g.CellCenter(5, 5)).value, 0.8, 1e-6);
  EXPECT_NEAR(dut.SpeedLimit(g.CellCenter(30, 30)).value, 1.1, 1e-6);
  // (cell centres read up to 1e-8 into the next cell) halfway between 0.01 and 0.03: halfway
  // between the open and the rough speed
  EXPECT_NEAR(dut.SpeedLimit(g.CellCenter(10, 30)).value, 1.3, 1e-6);
  EXPECT_NEAR(dut.SpeedLimit(g.CellCenter(31, 30)).value, 1.5, 1e-6);
  EXPECT_NEAR(dut.SpeedLimit(g.CellCenter(20, 20)).value, 1.5, 1e-6);
  // bilinear between cells, with its gradient
  const FieldSample between = dut.SpeedLimit(0.5 * (g.CellCenter(30, 30) + g.CellCenter(31, 30)));
  EXPECT_NEAR(between.value, 1.3, 1e-6);
  EXPECT_NEAR(between.gradient_W.x(), 0.4 / 0.1, 1e-5);
  // with a reach of 0.2 m every cell within 2 cells (a disc) takes the rough cell's limit
  config.speed.reach_m = 0.2;
  const CostField wide(map, config);
  EXPECT_NEAR(wide.SpeedLimit(g.CellCenter(32, 30)).value, 1.1, 1e-6);
  EXPECT_NEAR(wide.SpeedLimit(g.CellCenter(31, 31)).value, 1.1, 1e-6);
  EXPECT_NEAR(wide.SpeedLimit(g.CellCenter(32, 32)).value, 1.5, 1e-6);
  EXPECT_NEAR(wide.SpeedLimit(g.CellCenter(33, 30)).value, 1.5, 1e-6);
  // the terrain never raises the limit above the open speed
  config.speed.unknown_m_s = 5.0;
  EXPECT_NEAR(CostField(map, config).SpeedLimit(g.CellCenter(5, 5)).value, 1.5, 1e-6);
}

TEST(CostFieldTest, NearLethalCellsTheElevationIsTheSurroundingGroundsNotTheObstaclesFoot) {
  // ground rising 0.2 m per m along x; a column of radius 0.3 m at the origin, whose mapped
  // elevation climbs 1 m per m toward it within 0.8 m (the regression's ramp up its foot); one
  // unknown cell beside it
  common::GridLayers map(
      common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(10, 10), 0.1),
      {"traversability", "elevation"});
  const common::GridGeometry& g = map.geometry();
  auto plane = [](const Eigen::Vector2d& p) { return 0.2 * p.x(); };
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      const Eigen::Vector2d p = g.CellCenter(ix, iy);
      map.Layer("traversability")(ix, iy) = p.norm() < 0.3 ? 1.0f : 0.0f;
      map.Layer("elevation")(ix, iy) = static_cast<float>(plane(p) + std::max(0.0, 0.8 - p.norm()));
    }
  }
  const Eigen::Vector2i unknown = *g.CellIndex({0.0, -0.6});
  map.Layer("elevation")(unknown.x(), unknown.y()) = std::numeric_limits<float>::quiet_NaN();
  CostMapConfig config;
  config.slope.max_pitch_deg = 40.0;
  config.slope.max_roll_deg = 40.0;
  const CostField field(map, config);
  ASSERT_EQ(CostField::kGroundReach_m, 1.0);
  // beyond the reach the map's elevation itself
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(3.05, 2.05), Eigen::Vector2d(-1.55, 0.05)}) {
    EXPECT_NEAR(field.Elevation(p).value, plane(p), 1e-6);
    EXPECT_NEAR(field.Elevation(p).gradient_W.x(), 0.2, 1e-5);
    EXPECT_NEAR(field.Elevation(p).gradient_W.y(), 0.0, 1e-5);
  }
  // within it, on every side of the column, no ramp (the map's slope there is at least 0.8 m per
  // m): the ground's is the plane's, up to the fill's smoothing
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(0.55, 0.05), Eigen::Vector2d(-0.55, 0.05),
                                   Eigen::Vector2d(0.05, 0.55), Eigen::Vector2d(0.35, 0.35)}) {
    const FieldSample ground = field.Elevation(p);
    EXPECT_NEAR(ground.gradient_W.x(), 0.2, 0.05) << p.transpose();
    EXPECT_NEAR(ground.gradient_W.y(), 0.0, 0.05) << p.transpose();
    EXPECT_NEAR(ground.value, plane(p), 0.05) << p.transpose();
  }
  // an unknown cell stays unknown
  EXPECT_TRUE(std::isnan(field.Elevation(g.CellCenter(unknown.x(), unknown.y())).value));
  // with the limits off (89 deg) no elevation is read
  EXPECT_TRUE(std::isnan(CostField(map, CostMapConfig{}).Elevation({3.05, 2.05}).value));
}

TEST(MinimumWithinDiscTest, EqualsTheBruteForceMinimumOverTheDisc) {
  common::Random random(7);
  Eigen::MatrixXd values(23, 17);
  for (Eigen::Index i = 0; i < values.size(); ++i) values.data()[i] = random.Uniform(0.0, 1.0);
  for (const int radius : {0, 1, 2, 5, 30}) {
    const Eigen::MatrixXd dut = MinimumWithinDisc(values, radius);
    for (int ix = 0; ix < values.rows(); ++ix) {
      for (int iy = 0; iy < values.cols(); ++iy) {
        double expected = values(ix, iy);
        for (int jx = 0; jx < values.rows(); ++jx) {
          for (int jy = 0; jy < values.cols(); ++jy) {
            if ((jx - ix) * (jx - ix) + (jy - iy) * (jy - iy) <= radius * radius)
              expected = std::min(expected, values(jx, jy));
          }
        }
        ASSERT_EQ(dut(ix, iy), expected) << "radius " << radius << " at " << ix << "," << iy;
      }
    }
  }
}

}  // namespace
}  // namespace trav::planner
