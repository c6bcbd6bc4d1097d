#include "planner/obstacle_memory.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace trav::planner {
namespace {

constexpr float kUnknown = std::numeric_limits<float>::quiet_NaN();

// A 2 x 2 m map at 0.5 m (5 x 5 cells) centred on center_W, every cell cost 0.
common::GridLayers SmallMap(const Eigen::Vector2d& center_W) {
  common::GridLayers map(common::GridGeometry::Centered(center_W, Eigen::Vector2d(2, 2), 0.5),
                         {"traversability"});
  map.Layer("traversability").setZero();
  return map;
}

void Set(common::GridLayers* map, const Eigen::Vector2d& p_W, float cost) {
  const Eigen::Vector2i cell = *map->geometry().CellIndex(p_W);
  map->Layer("traversability")(cell.x(), cell.y()) = cost;
}

void Record(ObstacleMemory* memory, const common::GridLayers& map) {
  memory->Record(map.geometry(), map.Layer("traversability"), CostMapConfig{});
}

TEST(ObstacleMemoryTest, CoversTheAreaOnTheMapsLattice) {
  const common::GridLayers map = SmallMap(Eigen::Vector2d::Zero());
  const ObstacleMemory dut(Eigen::AlignedBox2d(Eigen::Vector2d(-3, -2), Eigen::Vector2d(3.1, 2)),
                           map.geometry());
  EXPECT_EQ(dut.geometry().origin_W, Eigen::Vector2d(-3, -2));
  EXPECT_EQ(dut.geometry().resolution_m, 0.5);
  EXPECT_EQ(dut.geometry().num_x, 13);
  EXPECT_EQ(dut.geometry().num_y, 9);
  EXPECT_TRUE(dut.SharesLattice(map.geometry()));
  EXPECT_TRUE(dut.SharesLattice(SmallMap(Eigen::Vector2d(1.5, -0.5)).geometry()));
  EXPECT_FALSE(dut.SharesLattice(SmallMap(Eigen::Vector2d(0.25, 0)).geometry()));
  common::GridGeometry finer = map.geometry();
  finer.resolution_m = 0.25;
  EXPECT_FALSE(dut.SharesLattice(finer));
}

TEST(ObstacleMemoryTest, RemembersLethalCellsUntilTheyAreSeenFree) {
  ObstacleMemory dut(Eigen::AlignedBox2d(Eigen::Vector2d(-2, -2), Eigen::Vector2d(2, 2)),
                     SmallMap(Eigen::Vector2d::Zero()).geometry());
  common::GridLayers map = SmallMap(Eigen::Vector2d::Zero());
  Set(&map, {0.5, 0.0}, 0.8f);  // at the lethal threshold
  Set(&map, {-0.5, 0.0}, 0.79f);
  Set(&map, {0.0, 0.5}, 1.0f);
  Record(&dut, map);
  EXPECT_TRUE(dut.Blocked({0.5, 0.0}));
  EXPECT_TRUE(dut.Blocked({0.6, 0.1}));  // the cell nearest to the point
  EXPECT_TRUE(dut.Blocked({0.0, 0.5}));
  EXPECT_FALSE(dut.Blocked({-0.5, 0.0}));
  EXPECT_FALSE(dut.Blocked({0.0, 0.0}));
  EXPECT_FALSE(dut.Blocked({5.0, 0.0}));  // off the grid
  // unknown: the memory keeps what it saw; known below the threshold: free
  Set(&map, {0.5, 0.0}, kUnknown);
  Set(&map, {0.0, 0.5}, 0.2f);
  Record(&dut, map);
  EXPECT_TRUE(dut.Blocked({0.5, 0.0}));
  EXPECT_FALSE(dut.Blocked({0.0, 0.5}));
  // a map that has rolled on, half off the memory's grid: its cells on the grid are taken, the
  // cells it no longer shows kept
  Set(&map, {1.0, -1.0}, 1.0f);
  Record(&dut, map);
  EXPECT_TRUE(dut.Blocked({1.0, -1.0}));
  common::GridLayers rolled = SmallMap(Eigen::Vector2d(2.0, -1.0));
  Set(&rolled, {2.0, -1.5}, 1.0f);
  Set(&rolled, {2.5, -1.5}, 1.0f);  // off the grid
  Set(&rolled, {3.0, -1.0}, 1.0f);  // off the grid
  Record(&dut, rolled);
  EXPECT_TRUE(dut.Blocked({2.0, -1.5}));
  EXPECT_TRUE(dut.Blocked({0.5, 0.0}));
  EXPECT_FALSE(dut.Blocked({1.0, -1.0}));  // seen free again
  // nothing written off the grid wrapped round onto it
  for (int ix = 0; ix < dut.geometry().num_x; ++ix) {
    for (int iy = 0; iy < dut.geometry().num_y; ++iy) {
      const Eigen::Vector2d p_W = dut.geometry().CellCenter(ix, iy);
      const bool blocked = (p_W - Eigen::Vector2d(2.0, -1.5)).norm() < 1e-9 ||
                           (p_W - Eigen::Vector2d(0.5, 0.0)).norm() < 1e-9;
      EXPECT_EQ(dut.Blocked(p_W), blocked) << p_W.transpose();
    }
  }
}

TEST(ObstacleMemoryTest, ASegmentIsObstructedWhereItCrossesABlockedCell) {
  ObstacleMemory dut(Eigen::AlignedBox2d(Eigen::Vector2d(-2, -2), Eigen::Vector2d(2, 2)),
                     SmallMap(Eigen::Vector2d::Zero()).geometry());
  common::GridLayers map = SmallMap(Eigen::Vector2d::Zero());
  Set(&map, {0.5, 0.0}, 1.0f);
  Set(&map, {0.5, 0.5}, 1.0f);
  Record(&dut, map);
  EXPECT_TRUE(dut.Obstructed({-1.5, 0.0}, {1.5, 0.0}));
  EXPECT_TRUE(dut.Obstructed({-1.5, 0.5}, {1.5, 0.0}));
  EXPECT_TRUE(dut.Obstructed({0.5, 0.0}, {0.5, 0.0}));  // a point in a blocked cell
  EXPECT_FALSE(dut.Obstructed({-1.5, -0.5}, {1.5, -0.5}));
  EXPECT_FALSE(dut.Obstructed({-1.5, 1.0}, {1.5, 1.0}));
  EXPECT_FALSE(dut.Obstructed({0.0, -1.5}, {0.0, 1.5}));
}

// A 5 x 3 grid at 1 m (cells (0, 0) to (4, 2)) with a wall at x = 2 open at its top cell.
ObstacleMemory WallWithAGap() {
  ObstacleMemory memory(Eigen::AlignedBox2d(Eigen::Vector2d(0, 0), Eigen::Vector2d(4, 2)),
                        common::GridGeometry{Eigen::Vector2d::Zero(), 1.0, 1, 1});
  for (const Eigen::Vector2d& wall : {Eigen::Vector2d(2, 0), Eigen::Vector2d(2, 1)}) {
    // a one-cell map of the wall's cell
    memory.Record(common::GridGeometry{wall, 1.0, 1, 1}, Eigen::MatrixXf::Ones(1, 1),
                  CostMapConfig{});
  }
  return memory;
}

TEST(ObstacleMemoryTest, DistancesGoRoundTheRememberedObstaclesWithoutCuttingCorners) {
  const ObstacleMemory dut = WallWithAGap();
  const Eigen::MatrixXd distance_m = dut.DistancesFrom({0, 0});
  EXPECT_EQ(distance_m(0, 0), 0.0);
  EXPECT_NEAR(distance_m(1, 1), std::sqrt(2.0), 1e-12);
  // through the gap, and no diagonal step past a blocked cell's corner: (1, 1) -> (2, 2) and
  // (2, 2) -> (3, 1) are not taken (they would make these 2 sqrt(2) and 2 + 2 sqrt(2))
  EXPECT_NEAR(distance_m(2, 2), 2.0 + std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(distance_m(3, 1), 4.0 + std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(distance_m(4, 0), 4.0 + 2.0 * std::sqrt(2.0), 1e-12);
  EXPECT_TRUE(std::isinf(distance_m(2, 0)));
  EXPECT_TRUE(std::isinf(distance_m(2, 1)));
  // a goal off the grid starts from the cell nearest to it; a blocked goal cell is still the source
  EXPECT_EQ(dut.DistancesFrom({9, -3})(4, 0), 0.0);
  const Eigen::MatrixXd from_wall = dut.DistancesFrom({2, 0});
  EXPECT_EQ(from_wall(2, 0), 0.0);
  EXPECT_EQ(from_wall(1, 0), 1.0);
  EXPECT_EQ(from_wall(3, 0), 1.0);
  EXPECT_TRUE(std::isinf(from_wall(2, 1)));
}

}  // namespace
}  // namespace trav::planner
