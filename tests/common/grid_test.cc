#include "common/grid.h"

#include <cmath>

#include <gtest/gtest.h>

namespace trav::common {
namespace {

TEST(GridGeometryTest, CenteredGridIncludesBothBorders) {
  const GridGeometry dut =
      GridGeometry::Centered(Eigen::Vector2d(1.0, -2.0), Eigen::Vector2d(4.0, 2.0), 0.5);
  EXPECT_EQ(dut.num_x, 9);
  EXPECT_EQ(dut.num_y, 5);
  EXPECT_DOUBLE_EQ(dut.origin_W.x(), -1.0);
  EXPECT_DOUBLE_EQ(dut.origin_W.y(), -3.0);
  EXPECT_DOUBLE_EQ(dut.CellCenter(8, 4).x(), 3.0);
  EXPECT_DOUBLE_EQ(dut.CellCenter(8, 4).y(), -1.0);
  EXPECT_TRUE(dut.Center().isApprox(Eigen::Vector2d(1.0, -2.0)));
}

TEST(GridGeometryTest, CellIndexRoundsToNearestCentreAndRejectsOutside) {
  const GridGeometry dut =
      GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(2.0, 2.0), 1.0);
  const auto cell = dut.CellIndex(Eigen::Vector2d(0.4, -0.6));
  ASSERT_TRUE(cell.has_value());
  EXPECT_EQ(cell->x(), 1);
  EXPECT_EQ(cell->y(), 0);
  EXPECT_FALSE(dut.CellIndex(Eigen::Vector2d(1.6, 0.0)).has_value());
  EXPECT_FALSE(dut.CellIndex(Eigen::Vector2d(0.0, -1.6)).has_value());
}

TEST(GridGeometryTest, TheNearestLatticeIndexGoesOnBeyondTheGrid) {
  const GridGeometry dut =
      GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(2.0, 2.0), 1.0);
  EXPECT_EQ(dut.NearestLatticeIndex(Eigen::Vector2d(0.4, -0.6)), Eigen::Vector2i(1, 0));
  EXPECT_EQ(dut.NearestLatticeIndex(Eigen::Vector2d(1.6, 0.0)), Eigen::Vector2i(3, 1));
  EXPECT_EQ(dut.NearestLatticeIndex(Eigen::Vector2d(-2.7, -1.6)), Eigen::Vector2i(-2, -1));
}

TEST(GridGeometryTest, AnyCellWithinVisitsTheCellsOfTheDiscOnTheGrid) {
  // 11 x 11 cells of 1 m; a marked cell at (7, 5), 2 m from the centre (5, 5)
  const GridGeometry g =
      GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(10.0, 10.0), 1.0);
  const auto marked = [](int ix, int iy) { return ix == 7 && iy == 5; };
  EXPECT_TRUE(AnyCellWithin(g, Eigen::Vector2d(0.0, 0.0), 2.0, marked));
  EXPECT_FALSE(AnyCellWithin(g, Eigen::Vector2d(0.0, 0.0), 1.99, marked));
  // the disc is round: (7, 7) lies 2.83 m away, outside a 2.5 m disc that reaches (7, 5)
  const auto corner = [](int ix, int iy) { return ix == 7 && iy == 7; };
  EXPECT_FALSE(AnyCellWithin(g, Eigen::Vector2d(0.0, 0.0), 2.5, corner));
  // the cells visited: those of the grid within the radius, at the border too
  int visited = 0;
  EXPECT_FALSE(AnyCellWithin(g, Eigen::Vector2d(-5.0, -5.0), 1.0, [&](int ix, int iy) {
    EXPECT_TRUE(g.Contains(ix, iy));
    ++visited;
    return false;
  }));
  EXPECT_EQ(visited, 3);  // (0, 0), (1, 0), (0, 1)
  // off the grid: no cell, whatever the radius
  EXPECT_FALSE(AnyCellWithin(g, Eigen::Vector2d(6.0, 0.0), 3.0, [](int, int) { return true; }));
}

TEST(GridGeometryTest, BilinearInterpolationIsExactOnAPlaneAndClampsOutside) {
  const GridGeometry geometry =
      GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(4.0, 4.0), 1.0);
  Eigen::MatrixXf layer(geometry.num_x, geometry.num_y);
  for (int ix = 0; ix < geometry.num_x; ++ix) {
    for (int iy = 0; iy < geometry.num_y; ++iy) {
      const Eigen::Vector2d p = geometry.CellCenter(ix, iy);
      layer(ix, iy) = static_cast<float>(2.0 * p.x() - 0.5 * p.y() + 1.0);
    }
  }
  EXPECT_FLOAT_EQ(InterpolateBilinear(geometry, layer, Eigen::Vector2d(0.25, -1.5)),
                  2.0f * 0.25f + 0.75f + 1.0f);
  EXPECT_FLOAT_EQ(InterpolateBilinear(geometry, layer, Eigen::Vector2d(2.0, 2.0)), 4.0f);
  // beyond the border the value of the border is used
  EXPECT_FLOAT_EQ(InterpolateBilinear(geometry, layer, Eigen::Vector2d(10.0, 2.0)), 4.0f);
}

TEST(GridLayersTest, NewLayersAreUnknownAndQueriesFollowTheGeometry) {
  GridLayers dut(GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(4, 4), 1.0),
                 {"a", "b"});
  EXPECT_EQ(dut.LayerNames(), (std::vector<std::string>{"a", "b"}));
  EXPECT_TRUE(std::isnan(dut.Layer("a")(2, 2)));
  EXPECT_FALSE(dut.At("a", Eigen::Vector2d(0, 0)).has_value());
  dut.Layer("a")(3, 1) = 7.0f;
  EXPECT_EQ(dut.At("a", Eigen::Vector2d(1.1, -0.9)), 7.0f);
  EXPECT_FALSE(dut.At("a", Eigen::Vector2d(9, 0)).has_value());
  EXPECT_THROW(dut.Layer("c"), std::out_of_range);
}

TEST(GridLayersTest, RecenteringKeepsCellsAnchoredInTheWorld) {
  GridLayers dut(GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(10, 10), 0.5),
                 {"v"});
  // mark every cell with a function of its world position
  auto mark = [](const Eigen::Vector2d& p) { return static_cast<float>(100.0 * p.x() + p.y()); };
  for (int ix = 0; ix < dut.geometry().num_x; ++ix) {
    for (int iy = 0; iy < dut.geometry().num_y; ++iy)
      dut.Layer("v")(ix, iy) = mark(dut.geometry().CellCenter(ix, iy));
  }
  const GridGeometry before = dut.geometry();
  EXPECT_EQ(before.RecenterShift(Eigen::Vector2d(3.1, -1.9)), Eigen::Vector2i(6, -4));
  dut.Recenter(Eigen::Vector2d(3.1, -1.9));
  EXPECT_TRUE(dut.geometry().Center().isApprox(Eigen::Vector2d(3.0, -2.0)));
  // the geometry a recentring gives, known before it
  const GridGeometry predicted = before.RecenteredOn(Eigen::Vector2d(3.1, -1.9));
  EXPECT_TRUE(predicted == dut.geometry());
  EXPECT_TRUE(predicted != before);
  // any field apart makes other cells
  GridGeometry other = predicted;
  other.num_y += 1;
  EXPECT_FALSE(other == predicted);
  other = predicted;
  other.resolution_m = 0.25;
  EXPECT_TRUE(other != predicted);
  int kept = 0, unknown = 0;
  for (int ix = 0; ix < dut.geometry().num_x; ++ix) {
    for (int iy = 0; iy < dut.geometry().num_y; ++iy) {
      const Eigen::Vector2d p = dut.geometry().CellCenter(ix, iy);
      const float value = dut.Layer("v")(ix, iy);
      const bool was_inside = std::abs(p.x()) <= 5.0 + 1e-9 && std::abs(p.y()) <= 5.0 + 1e-9;
      if (was_inside) {
        ASSERT_FLOAT_EQ(value, mark(p));
        ++kept;
      } else {
        ASSERT_TRUE(std::isnan(value));
        ++unknown;
      }
    }
  }
  EXPECT_EQ(kept, 15 * 17);
  EXPECT_EQ(unknown, 21 * 21 - 15 * 17);
  // 20 m away: nothing is left
  dut.Recenter(Eigen::Vector2d(23.0, -2.0));
  EXPECT_TRUE(dut.Layer("v").array().isNaN().all());
}

TEST(GridLayersTest, RecenteringShiftsEveryCellByTheWholeCellsMovedInEveryDirection) {
  // shifts along x and y of either sign, along one axis only, and beyond the grid
  for (const int dx : {-9, -3, -1, 0, 2, 7}) {
    for (const int dy : {-8, -2, 0, 1, 4, 9}) {
      if (dx == 0 && dy == 0) continue;
      GridLayers dut(GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(3, 4), 0.5),
                     {"a", "b"});
      const int nx = dut.geometry().num_x, ny = dut.geometry().num_y;  // 7 x 9
      for (int ix = 0; ix < nx; ++ix) {
        for (int iy = 0; iy < ny; ++iy) {
          dut.Layer("a")(ix, iy) = static_cast<float>(100 * ix + iy);
          dut.Layer("b")(ix, iy) = static_cast<float>(-100 * ix - iy);
        }
      }
      dut.Recenter(Eigen::Vector2d(0.5 * dx, 0.5 * dy));
      for (int ix = 0; ix < nx; ++ix) {
        for (int iy = 0; iy < ny; ++iy) {
          const int from_x = ix + dx, from_y = iy + dy;
          if (from_x >= 0 && from_x < nx && from_y >= 0 && from_y < ny) {
            EXPECT_EQ(dut.Layer("a")(ix, iy), static_cast<float>(100 * from_x + from_y))
                << dx << " " << dy << " " << ix << " " << iy;
            EXPECT_EQ(dut.Layer("b")(ix, iy), static_cast<float>(-100 * from_x - from_y));
          } else {
            EXPECT_TRUE(std::isnan(dut.Layer("a")(ix, iy))) << dx << " " << dy;
            EXPECT_TRUE(std::isnan(dut.Layer("b")(ix, iy))) << dx << " " << dy;
          }
        }
      }
    }
  }
}

TEST(RoughnessTest, IsZeroOnAPlaneAndHalfAStepAtItsEdge) {
  Eigen::MatrixXf heights(5, 5);
  for (int ix = 0; ix < 5; ++ix) {
    for (int iy = 0; iy < 5; ++iy) heights(ix, iy) = 0.3f * static_cast<float>(ix - 2 * iy);
  }
  for (int ix = 0; ix < 5; ++ix) {
    for (int iy = 0; iy < 5; ++iy) EXPECT_NEAR(Roughness(heights, ix, iy), 0.0, 1e-6);
  }
  // a 0.12 m step between ix = 2 and 3: 0.06 on either side of it, 0 elsewhere
  for (int ix = 0; ix < 5; ++ix) heights.row(ix).setConstant(ix >= 3 ? 0.12f : 0.0f);
  for (int iy = 0; iy < 5; ++iy) {
    EXPECT_NEAR(Roughness(heights, 1, iy), 0.0, 1e-7);
    EXPECT_NEAR(Roughness(heights, 2, iy), 0.06, 1e-7);
    EXPECT_NEAR(Roughness(heights, 3, iy), 0.06, 1e-7);
    EXPECT_NEAR(Roughness(heights, 4, iy), 0.0, 1e-7);
  }
  // directions with an unknown height are left out; none left: 0
  heights(1, 2) = std::numeric_limits<float>::quiet_NaN();
  heights(2, 1) = heights(1, 1) = heights(1, 3) = heights(2, 3) = heights(3, 1) = heights(3, 3) =
      std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(Roughness(heights, 2, 2), 0.0);
  heights(2, 3) = 0.0f;
  EXPECT_NEAR(Roughness(heights, 2, 2), 0.0, 1e-7);
}

}  // namespace
}  // namespace trav::common
