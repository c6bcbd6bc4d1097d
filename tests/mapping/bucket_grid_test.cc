#include "mapping/bucket_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "common/random.h"

namespace trav::mapping {
namespace {

TEST(BucketGridTest, HoldsEveryPointOnceInTheBucketOfItsPosition) {
  // five points over [1, 3.5] x [-1, 0] in 1 m buckets: 3 x 2 buckets from (1, -1)
  Eigen::Matrix2Xd points(2, 5);
  points << 1.0, 1.5, 3.5, 2.2, 1.0,  //
      -1.0, -0.2, 0.0, -0.9, -1.0;
  const BucketGrid dut(points, 1.0);
  EXPECT_EQ(dut.origin(), Eigen::Vector2d(1.0, -1.0));
  EXPECT_EQ(dut.count(), Eigen::Vector2i(3, 2));
  std::vector<int> seen(5, 0);
  for (int by = 0; by < 2; ++by) {
    for (int bx = 0; bx < 3; ++bx) {
      std::vector<int> in_bucket;
      dut.ForPointsIn(Eigen::Vector2i(bx, by), [&](int j) { in_bucket.push_back(j); });
      for (int j : in_bucket) {
        ++seen[static_cast<std::size_t>(j)];
        EXPECT_EQ(dut.BucketOf(points.col(j)), Eigen::Vector2i(bx, by)) << "point " << j;
      }
      // indices ascend within a bucket (the order of the input)
      EXPECT_TRUE(std::is_sorted(in_bucket.begin(), in_bucket.end()));
    }
  }
  EXPECT_EQ(seen, std::vector<int>(5, 1));
  EXPECT_EQ(dut.BucketOf(Eigen::Vector2d(2.2, -0.9)), Eigen::Vector2i(1, 0));
  EXPECT_EQ(dut.BucketOf(Eigen::Vector2d(3.5, 0.0)), Eigen::Vector2i(2, 1));
  // outside: clamped to the border; buckets beyond the grid hold nothing
  EXPECT_EQ(dut.BucketOf(Eigen::Vector2d(-50.0, 1e12)), Eigen::Vector2i(0, 1));
  int outside = 0;
  dut.ForPointsIn(Eigen::Vector2i(-1, 0), [&](int) { ++outside; });
  dut.ForPointsIn(Eigen::Vector2i(3, 1), [&](int) { ++outside; });
  EXPECT_EQ(outside, 0);
}

TEST(BucketGridTest, AnEmptySetHasNoBuckets) {
  const BucketGrid dut(Eigen::Matrix2Xd(2, 0), 1.0);
  EXPECT_EQ(dut.count(), Eigen::Vector2i(0, 0));
  int visited = 0;
  dut.ForPointsIn(Eigen::Vector2i(0, 0), [&](int) { ++visited; });
  EXPECT_EQ(visited, 0);
}

TEST(BucketGridTest, ThinlySpreadPointsGetLargerBucketsNotMoreOfThem) {
  // two points 1 km apart in 1 m buckets would need a million buckets: at most 4 per point (+16)
  Eigen::Matrix2Xd points(2, 2);
  points << 0.0, 1000.0,  //
      0.0, 1000.0;
  const BucketGrid dut(points, 1.0);
  EXPECT_LE(dut.count().prod(), 4 * 2 + 16);
  EXPECT_GT(dut.bucket_size(), 1.0);
  EXPECT_EQ(dut.BucketOf(points.col(0)), Eigen::Vector2i(0, 0));
  EXPECT_EQ(dut.BucketOf(points.col(1)), (dut.count().array() - 1).matrix());
}

// The k nearest under a 3-D distance, from buckets over (x, y), against sorting every point; and
// a support radius that stops the search early.
TEST(BucketGridTest, KNearestInThreeDimensionsMatchesABruteForceSearch) {
  common::Random random(3);
  Eigen::Matrix3Xd points(3, 400);
  for (int j = 0; j < 400; ++j) {
    // a floor and a wall: many points share a bucket in (x, y) at different heights
    const bool wall = j % 4 == 0;
    points.col(j) << (wall ? 1.0 : random.Uniform(-2, 2)), random.Uniform(-2, 2),
        (wall ? random.Uniform(0, 1.5) : 0.0);
  }
  BucketGrid dut;
  dut.Rebuild(points.topRows<2>(), BucketGrid::SideFor(points.topRows<2>(), 5.0));
  std::vector<BucketGrid::Neighbour> found;
  for (int q = 0; q < 400; q += 7) {
    const Eigen::Vector3d p = points.col(q);
    dut.KNearest(
        p.head<2>(), 20, std::numeric_limits<double>::infinity(),
        [&](int j) { return (points.col(j) - p).norm(); }, &found);
    std::vector<BucketGrid::Neighbour> all;
    for (int j = 0; j < 400; ++j) all.emplace_back((points.col(j) - p).norm(), j);
    std::sort(all.begin(), all.end());
    all.resize(20);
    EXPECT_EQ(found, all) << "query " << q;
  }
  // nothing within 0.1 m of a query 5 m away: the search stops, its nearest lies beyond
  dut.KNearest(
      Eigen::Vector2d(7.0, 0.0), 20, 0.1,
      [&](int j) { return (points.col(j).head<2>() - Eigen::Vector2d(7.0, 0.0)).norm(); }, &found);
  EXPECT_TRUE(found.empty() || found.front().first > 0.1);
}

// By squared distance (kSquared): the same neighbours in the same order as by distance, with the
// squares of their distances; the support radius stops the search where it does by distance.
TEST(BucketGridTest, KNearestBySquaredDistanceFindsTheSameNeighboursInTheSameOrder) {
  common::Random random(5);
  Eigen::Matrix3Xd points(3, 500);
  for (int j = 0; j < 500; ++j) {
    points.col(j) << random.Uniform(-3, 3), random.Uniform(-3, 3), random.Uniform(0, 0.5);
  }
  BucketGrid dut;
  dut.Rebuild(points.topRows<2>(), BucketGrid::SideFor(points.topRows<2>(), 2.0));
  std::vector<BucketGrid::Neighbour> by_distance, by_square;
  int stopped_early = 0;
  for (int q = 0; q < 60; ++q) {
    const Eigen::Vector3d p(random.Uniform(-4, 4), random.Uniform(-4, 4), random.Uniform(0, 0.5));
    const double support_m = q % 2 == 0 ? std::numeric_limits<double>::infinity() : 0.15;
    dut.KNearest(
        p.head<2>(), 8, support_m, [&](int j) { return (points.col(j) - p).norm(); }, &by_distance);
    dut.KNearest<true>(
        p.head<2>(), 8, support_m, [&](int j) { return (points.col(j) - p).squaredNorm(); },
        &by_square);
    ASSERT_EQ(by_square.size(), by_distance.size()) << "query " << q;
    for (std::size_t i = 0; i < by_square.size(); ++i) {
      EXPECT_EQ(by_square[i].second, by_distance[i].second) << "query " << q << ", place " << i;
      EXPECT_EQ(std::sqrt(by_square[i].first), by_distance[i].first) << "query " << q;
    }
    if (by_distance.size() < 8) ++stopped_early;
  }
  // the radius cut some searches short: the stop was compared too
  EXPECT_GT(stopped_early, 0);
}

// On a lattice many points lie at the same distance from a query: the k-th place goes to the lower
// index among them, as in a sort of every (distance, index), whatever order the buckets are
// visited in.
TEST(BucketGridTest, KNearestBreaksTiesByIndexOnALattice) {
  Eigen::Matrix2Xd points(2, 121);
  // quarter metres: exact in binary, so that the distances tie exactly
  for (int j = 0; j < 121; ++j) points.col(j) << 0.25 * (j % 11), 0.25 * (j / 11);
  BucketGrid dut;
  dut.Rebuild(points, 0.6);
  std::vector<BucketGrid::Neighbour> found;
  for (int q : {0, 17, 60, 120}) {
    for (int k : {5, 9, 13, 21}) {
      const Eigen::Vector2d p = points.col(q);
      dut.KNearest(
          p, k, std::numeric_limits<double>::infinity(),
          [&](int j) { return (points.col(j) - p).norm(); }, &found);
      std::vector<BucketGrid::Neighbour> all;
      for (int j = 0; j < 121; ++j) all.emplace_back((points.col(j) - p).norm(), j);
      std::sort(all.begin(), all.end());
      all.resize(static_cast<std::size_t>(k));
      EXPECT_EQ(found, all) << "query " << q << ", k " << k;
    }
  }
}

}  // namespace
}  // namespace trav::mapping
