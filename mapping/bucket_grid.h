#pragma once

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace trav::mapping {

/// Points of the plane sorted into square buckets over their bounding box, stored compressed (the
/// point indices ordered by bucket, and where each bucket starts). The neighbour structure of the
/// mapper: for a few hundred to a few thousand points a kd-tree costs more to build than it saves,
/// and a grid rebuilt in place allocates nothing once its sizes have been seen (PCL's kd-tree
/// allocated its index on every frame).
class BucketGrid {
 public:
  /// A (distance, point index) pair of a neighbour search.
  using Neighbour = std::pair<double, int>;

  BucketGrid() = default;
  /// The most buckets per point: where points spread so thinly that buckets of the size asked for
  /// would be more, the buckets are made larger.
  static constexpr double kMaxBucketsPerPoint = 4.0;

  /// Buckets of side `bucket_size` (> 0, or larger: kMaxBucketsPerPoint) over the bounding box of
  /// `points` (one per column).
  BucketGrid(const Eigen::Ref<const Eigen::Matrix2Xd>& points, double bucket_size);

  /// Sorts `points` into buckets of side `bucket_size` (> 0, or larger: kMaxBucketsPerPoint),
  /// reusing the storage of earlier calls.
  void Rebuild(const Eigen::Ref<const Eigen::Matrix2Xd>& points, double bucket_size);

  /// A bucket side that puts about `per_bucket` of `points` in a bucket if they spread evenly over
  /// their bounding box (at least 1 mm).
  static double SideFor(const Eigen::Ref<const Eigen::Matrix2Xd>& points, double per_bucket);

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

  /// The `k` points nearest to `p` under `distance(j)`, sorted by (distance, index), into `found`
  /// (cleared first; it keeps its capacity). `distance(j)` may measure more than the plane (3-D
  /// points whose (x, y) were bucketed) but never less than the planar distance from `p` to point
  /// j: rings of buckets are searched outwards until no point beyond the ring can be nearer than
  /// the k-th found. The search also stops once the ring reaches past `support_radius` with nothing
  /// found within it: then `found` may hold fewer or farther points, and its first is beyond the
  /// radius (or it is empty). With `kSquared`, `distance(j)` gives the squared distance and so
  /// does `found`: the same neighbours in the same order (but for two whose squares differ and
  /// whose roots round to one value, ordered then by square, not index), without a square root
  /// per candidate (a caller that needs the distances takes the roots of the k found).
  template <bool kSquared = false, typename Distance>
  void KNearest(const Eigen::Vector2d& p, int k, double support_radius, Distance distance,
                std::vector<Neighbour>* found) const;

  /// Lower corner of bucket (0, 0).
  const Eigen::Vector2d& origin() const { return origin_; }
  double bucket_size() const { return bucket_size_; }
  /// Buckets along x and y.
  const Eigen::Vector2i& count() const { return count_; }

 private:
  Eigen::Vector2d origin_{Eigen::Vector2d::Zero()};
  double bucket_size_{1.0};
  Eigen::Vector2i count_{Eigen::Vector2i::Zero()};
  std::vector<int> start_;      // bucket b holds points_[start_[b] .. start_[b + 1])
  std::vector<int> points_;     // point indices, ordered by bucket
  std::vector<int> bucket_of_;  // the bucket of each point (scratch of Rebuild)
};

template <bool kSquared, typename Distance>
void BucketGrid::KNearest(const Eigen::Vector2d& p, int k, double support_radius, Distance distance,
                          std::vector<Neighbour>* found) const {
  found->clear();
  if (k <= 0 || points_.empty()) return;
  auto visit_bucket = [&](int bx, int by) {
    ForPointsIn(Eigen::Vector2i(bx, by), [&](int j) {
      const Neighbour candidate(distance(j), j);
      // an insertion from the back (k is a few dozen at most): the k-th falls out when full
      auto slot = static_cast<std::ptrdiff_t>(found->size());
      if (slot == k) {
        if (!(candidate < found->back())) return;
        --slot;
      } else {
        found->emplace_back();
      }
      Neighbour* sorted = found->data();
      for (; slot > 0 && candidate < sorted[slot - 1]; --slot) sorted[slot] = sorted[slot - 1];
      sorted[slot] = candidate;
    });
  };
  const Eigen::Vector2i centre = BucketOf(p);
  const int qx = centre.x(), qy = centre.y();
  // distance from the query to the outside of its bucket neighbourhood of `ring` rings
  const double inside_x = std::min(p.x() - (origin_.x() + qx * bucket_size_),
                                   origin_.x() + (qx + 1) * bucket_size_ - p.x());
  const double inside_y = std::min(p.y() - (origin_.y() + qy * bucket_size_),
                                   origin_.y() + (qy + 1) * bucket_size_ - p.y());
  const double inside = std::max(0.0, std::min(inside_x, inside_y));
  const int max_ring = count_.sum();  // rings beyond this hold nothing
  const double support_key = kSquared ? support_radius * support_radius : support_radius;
  for (int ring = 0;; ++ring) {
    if (ring == 0) {
      visit_bucket(qx, qy);
    } else {  // the ring's perimeter: top and bottom rows, then the sides between them
      for (int bx = qx - ring; bx <= qx + ring; ++bx) {
        visit_bucket(bx, qy - ring);
        visit_bucket(bx, qy + ring);
      }
      for (int by = qy - ring + 1; by <= qy + ring - 1; ++by) {
        visit_bucket(qx - ring, by);
        visit_bucket(qx + ring, by);
      }
    }
    // every point beyond this ring is at least `reach` away
    const double reach = inside + ring * bucket_size_;
    const double reach_key = kSquared ? reach * reach : reach;
    const bool covered = ring >= max_ring;
    const bool complete = static_cast<int>(found->size()) == k && found->back().first <= reach_key;
    const bool unsupported =
        reach > support_radius && (found->empty() || found->front().first > support_key);
    if (covered || complete || unsupported) return;
  }
}

}  // namespace trav::mapping
