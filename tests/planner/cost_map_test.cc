#include "planner/cost_map.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "planner/cost_field.h"

namespace trav::planner {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// A map of `size_m` x `size_m` at 0.1 m centred on the origin, every cell of cost `value`.
common::GridLayers ConstantMap(double size_m, float value) {
  common::GridLayers map(
      common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(size_m, size_m), 0.1),
      {"traversability"});
  map.Layer("traversability").setConstant(value);
  return map;
}

TEST(CostMapTest, SegmentCostOnAConstantMapIsTheLengthTimesOnePlusTheWeightedCost) {
  // 0.25 is exact in float and double, so the mean of the samples is exactly 0.25
  const SearchCostMap dut(ConstantMap(10.0, 0.25f), CostMapConfig{});
  const double per_metre = 1.0 + 5.0 * 0.25;
  EXPECT_DOUBLE_EQ(dut.SegmentCost({-4, 0}, {4, 0}), 8.0 * per_metre);
  const Eigen::Vector2d a(-3.0, -2.0), b(2.7, 3.1);
  EXPECT_DOUBLE_EQ(dut.SegmentCost(a, b), (b - a).norm() * per_metre);
  EXPECT_EQ(dut.SegmentCost(a, b), dut.SegmentCost(b, a));
  EXPECT_EQ(dut.SegmentCost(a, a), 0.0);
  EXPECT_EQ(dut.min_cost(), 0.25);
}

TEST(CostMapTest, SegmentCostAveragesSamplesHalfACellApart) {
  // cells with centres at x >= 0.1 cost 0.5, the others 0
  common::GridLayers map = ConstantMap(10.0, 0.0f);
  const common::GridGeometry& g = map.geometry();
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      if (g.CellCenter(ix, iy).x() > 0.05) map.Layer("traversability")(ix, iy) = 0.5f;
    }
  }
  CostMapConfig config;
  config.cost_weight = 6.0;
  const SearchCostMap dut(map, config);
  // 0.38 m at 0.05 m: 8 intervals of 0.0475 m, samples at x = -0.21 + 0.0475 k, k = 0..8, in the
  // cells -0.2, -0.2, -0.1, -0.1, 0, 0, 0.1, 0.1, 0.2: three of nine cost 0.5, mean 1/6
  EXPECT_DOUBLE_EQ(dut.SegmentCost({-0.21, 0.0}, {0.17, 0.0}), 0.38 * (1.0 + 6.0 / 6.0));
  EXPECT_EQ(dut.min_cost(), 0.0);
}

TEST(CostMapTest, ASegmentOverABlockedCellOrOffTheMapIsInfinite) {
  common::GridLayers map = ConstantMap(4.0, 0.0f);
  map.Layer("traversability")(20, 20) = 1.0f;  // the cell at the origin
  CostMapConfig config;
  config.inflation_radius_m = 0.0;
  const SearchCostMap dut(map, config);
  EXPECT_EQ(dut.CostAt({0.04, -0.04}), kInfinity);
  EXPECT_EQ(dut.CostAt({0.06, 0.0}), 0.0);
  EXPECT_EQ(dut.CostAt({2.1, 0.0}), kInfinity);  // outside the grid
  // the ends are free, a sample in the middle is not
  EXPECT_EQ(dut.SegmentCost({-1, 0}, {1, 0}), kInfinity);
  EXPECT_EQ(dut.SegmentCost({-1, 0.1}, {1, 0.1}), 2.0);
  EXPECT_EQ(dut.SegmentCost({-1, 0.1}, {2.5, 0.1}), kInfinity);
  EXPECT_EQ(dut.SegmentCost({-1, 0.1}, {std::nan(""), 0.1}), kInfinity);
}

TEST(CostMapTest, InflationBlocksCellsCloserToALethalCellThanItsRadius) {
  common::GridLayers map = ConstantMap(2.0, 0.25f);
  map.Layer("traversability")(10, 10) = 0.8f;    // at the threshold: lethal
  map.Layer("traversability")(13, 10) = 0.125f;  // cheaper, but inside the inflation
  for (const double radius_m : {0.3, 0.25}) {
    CostMapConfig config;
    config.inflation_radius_m = radius_m;
    const SearchCostMap dut(map, config);
    // the gap between cell boundaries, (centre distance - 0.5 cells) x 0.1 m, below the radius
    int blocked = 0;
    for (int ix = 0; ix < 21; ++ix) {
      for (int iy = 0; iy < 21; ++iy) {
        const double gap_m = (std::hypot(ix - 10, iy - 10) - 0.5) * 0.1;
        EXPECT_EQ(std::isinf(dut.cost(ix, iy)), gap_m < radius_m - 1e-12) << ix << ", " << iy;
        blocked += std::isinf(dut.cost(ix, iy)) ? 1 : 0;
      }
    }
    EXPECT_EQ(blocked, radius_m == 0.3 ? 37 : 25);
    EXPECT_EQ(dut.min_cost(), radius_m == 0.3 ? 0.25 : 0.125);
  }
}

TEST(CostMapTest, CellsOutsideTheOperatingAreaAreLethalForEveryPart) {
  // a free 4 x 4 m map, the area its left half (x <= 0)
  CostMapConfig config;
  config.inflation_radius_m = 0.3;
  config.operating_area_W.emplace(Eigen::Vector2d(-2.0, -2.0), Eigen::Vector2d(0.0, 2.0));
  const CostMap dut(ConstantMap(4.0, 0.0f), config);
  EXPECT_FALSE(dut.LethalAt({0.0, 0.0}));  // on the border: inside
  EXPECT_TRUE(dut.LethalAt({0.1, 0.0}));
  EXPECT_TRUE(dut.LethalAt({1.9, -1.9}));
  // the search keeps the inflation radius from the border: cells x = 0.1 are lethal, so centres
  // closer than 0.3 m + half a cell to them are blocked (x >= -0.2), the others free
  EXPECT_TRUE(std::isinf(dut.search().CostAt({-0.2, 0.5})));
  EXPECT_EQ(dut.search().CostAt({-0.3, 0.5}), 0.0);
  EXPECT_TRUE(std::isinf(dut.search().SegmentCost({-1.0, 0.0}, {1.0, 0.0})));
  // without an area the same map is free everywhere
  EXPECT_FALSE(CostMap(ConstantMap(4.0, 0.0f), CostMapConfig{}).LethalAt({1.9, -1.9}));
}

TEST(CostMapTest, TheBandChargesCellsNearTheInflationLinearlyLess) {
  common::GridLayers map = ConstantMap(2.0, 0.25f);
  map.Layer("traversability")(10, 10) = 1.0f;
  CostMapConfig config;
  config.inflation_radius_m = 0.15;
  config.band_radius_m = 0.55;
  config.band_cost = 0.4;
  const SearchCostMap dut(map, config);
  // along +x: gaps 0.05, 0.15, 0.25, ... m from the lethal cell's boundary
  EXPECT_TRUE(std::isinf(dut.cost(11, 10)));
  EXPECT_NEAR(dut.cost(12, 10), 0.25 + 0.4, 1e-12);              // gap 0.15: the band's inner edge
  EXPECT_NEAR(dut.cost(14, 10), 0.25 + 0.4 * 0.2 / 0.4, 1e-12);  // gap 0.35: half way
  EXPECT_EQ(dut.cost(16, 10), 0.25);                             // gap 0.55: outside
}

TEST(CostMapTest, UnknownCellsFollowThePolicyAndCostsAreClampedAtZero) {
  common::GridLayers map = ConstantMap(2.0, 0.25f);
  map.Layer("traversability")(3, 4) = std::numeric_limits<float>::quiet_NaN();
  map.Layer("traversability")(5, 6) = -0.5f;
  CostMapConfig config;
  config.unknown_cost = 0.75;
  EXPECT_EQ(SearchCostMap(map, config).cost(3, 4), 0.75);
  EXPECT_EQ(SearchCostMap(map, config).cost(5, 6), 0.0);
  config.unknown_policy = UnknownPolicy::kBlocked;
  EXPECT_EQ(SearchCostMap(map, config).cost(3, 4), kInfinity);
  // blocked unknown cells are not lethal: they do not grow
  EXPECT_EQ(SearchCostMap(map, config).cost(3, 5), 0.25);
}

// CostMap builds its searches and its field on one distance transform where their lethal cells
// agree: each part must read exactly as the same part built alone, under either unknown policy.
TEST(CostMapTest, ItsPartsAreThePartsBuiltAloneUnderEitherUnknownPolicy) {
  common::GridLayers map = ConstantMap(3.0, 0.25f);
  Eigen::MatrixXf& layer = map.Layer("traversability");
  for (int iy = 5; iy < 25; ++iy) layer(12, iy) = 1.0f;  // a wall along y
  layer(20, 15) = std::numeric_limits<float>::quiet_NaN();
  layer(21, 15) = std::numeric_limits<float>::quiet_NaN();
  CostMapConfig config;
  config.inflation_radius_m = 0.25;
  config.band_radius_m = 0.45;
  for (const UnknownPolicy policy : {UnknownPolicy::kCost, UnknownPolicy::kBlocked}) {
    SCOPED_TRACE(static_cast<int>(policy));
    config.unknown_policy = policy;
    const CostMap dut(map, config);
    const SearchCostMap search(map, config);
    CostMapConfig wide_config = config;
    wide_config.inflation_radius_m = config.band_radius_m;
    const SearchCostMap wide(map, wide_config);
    const CostField field(map, config);
    const common::GridGeometry& g = map.geometry();
    for (int ix = 0; ix < g.num_x; ++ix) {
      for (int iy = 0; iy < g.num_y; ++iy) {
        ASSERT_EQ(dut.search().cost(ix, iy), search.cost(ix, iy)) << ix << ", " << iy;
        ASSERT_EQ(dut.wide_search().cost(ix, iy), wide.cost(ix, iy)) << ix << ", " << iy;
        const Eigen::Vector2d c = g.CellCenter(ix, iy);
        ASSERT_EQ(dut.field().Distance(c).value, field.Distance(c).value) << ix << ", " << iy;
      }
    }
    // blocked unknown cells are obstacles to the field (a cell beside them 5 cm away, else the
    // wall 0.95 m away), never grown by the searches
    const double beside_unknown = dut.field().Distance(g.CellCenter(22, 15)).value;
    EXPECT_NEAR(beside_unknown, policy == UnknownPolicy::kBlocked ? 0.05 : 0.95, 1e-9);
    EXPECT_EQ(dut.search().cost(22, 15), 0.25);
  }
}

TEST(CostMapTest, AMapWithoutFreeCellsHasMinimumCostZeroAndAMissingLayerThrows) {
  EXPECT_EQ(SearchCostMap(ConstantMap(1.0, 1.0f), CostMapConfig{}).min_cost(), 0.0);
  CostMapConfig config;
  config.cost_layer = "roughness";
  EXPECT_THAT([&] { SearchCostMap(ConstantMap(1.0, 0.0f), config); },
              ThrowsMessage<std::out_of_range>(HasSubstr("roughness")));
}

}  // namespace
}  // namespace trav::planner
