#pragma once

#include <vector>

#include <Eigen/Core>

namespace trav::mapping {

/// Points of the plane sorted into square buckets over their bounding box, stored compressed (the
/// point indices ordered by bucket, and where each bucket starts). For neighbour searches among a
/// few hundred points, where a kd-tree costs more to build than it saves.
class BucketGrid {
 public:
  BucketGrid() = default;
  /// Buckets of side `bucket_size` (> 0) over the bounding box of `points` (one per column).
  BucketGrid(const Eigen::Ref<const Eigen::Matrix2Xd>& points, double bucket_size);

  /// The bucket holding `p`, clamped to the grid (points outside it go to the nearest border
  /// bucket).
  Eigen::Vector2i BucketOf(const Eigen::Vector2d& p) const;

  /// Calls visit(j) for every point j in bucket `b`; nothing when `b` is outside the grid.
  template <typename Visit>
  void ForPointsIn(const Eigen::Vector2i& b, Visit visit) const {
    if ((b.array() < 0).any() || (b.array() >= count_.array()).any()) return;
    const auto bucket = static_cast<std::size_t>(b.y() * count_.x() + b.x());
    for (int k = start_[bucket]; k < start_[bucket + 1]; ++k)
      visit(points_[static_cast<std::size_t>(k)]);
  }

  /// Lower corner of bucket (0, 0).
  const Eigen::Vector2d& origin() const { return origin_; }
  double bucket_size() const { return bucket_size_; }
  /// Buckets along x and y.
  const Eigen::Vector2i& count() const { return count_; }

 private:
  Eigen::Vector2d origin_{Eigen::Vector2d::Zero()};
  double bucket_size_{1.0};
  Eigen::Vector2i count_{Eigen::Vector2i::Zero()};
  std::vector<int> start_;   // bucket b holds points_[start_[b] .. start_[b + 1])
  std::vector<int> points_;  // point indices, ordered by bucket
};

}  // namespace trav::mapping
