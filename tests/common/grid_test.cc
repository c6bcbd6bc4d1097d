#include "common/grid.h"

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

}  // namespace
}  // namespace trav::common
