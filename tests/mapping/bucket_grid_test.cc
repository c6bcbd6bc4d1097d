#include "mapping/bucket_grid.h"

#include <algorithm>
#include <vector>

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace trav::mapping
