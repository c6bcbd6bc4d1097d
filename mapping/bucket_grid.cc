#include "mapping/bucket_grid.h"

#include <algorithm>
#include <cmath>

namespace trav::mapping {

BucketGrid::BucketGrid(const Eigen::Ref<const Eigen::Matrix2Xd>& points, double bucket_size) {
  Rebuild(points, bucket_size);
}

void BucketGrid::Rebuild(const Eigen::Ref<const Eigen::Matrix2Xd>& points, double bucket_size) {
  bucket_size_ = bucket_size;
  const Eigen::Index n = points.cols();
  points_.clear();
  start_.clear();
  if (n == 0) {
    origin_.setZero();
    count_.setZero();
    return;
  }
  origin_ = points.rowwise().minCoeff();
  const Eigen::Vector2d extent = points.rowwise().maxCoeff() - origin_;
  // at most kMaxBucketsPerPoint buckets per point, larger ones where the points spread thinly (a
  // bucket larger than asked for only makes searches visit more points): the storage is then
  // bounded by the number of points, and once a set of the size has been seen it fits
  const double max_buckets = kMaxBucketsPerPoint * static_cast<double>(n) + 16.0;
  count_ = (extent / bucket_size_).array().floor().cast<int>() + 1;
  while (count_.cast<double>().prod() > max_buckets) {
    bucket_size_ *= std::max(1.05, std::sqrt(count_.cast<double>().prod() / max_buckets));
    count_ = (extent / bucket_size_).array().floor().cast<int>() + 1;
  }
  bucket_of_.resize(static_cast<std::size_t>(n));
  start_.reserve(static_cast<std::size_t>(max_buckets) + 1);
  start_.assign(static_cast<std::size_t>(count_.prod()) + 1, 0);
  for (Eigen::Index j = 0; j < n; ++j) {
    const Eigen::Vector2i b = BucketOf(points.col(j));
    bucket_of_[static_cast<std::size_t>(j)] = b.y() * count_.x() + b.x();
    ++start_[static_cast<std::size_t>(bucket_of_[static_cast<std::size_t>(j)]) + 1];
  }
  for (std::size_t b = 1; b < start_.size(); ++b) start_[b] += start_[b - 1];
  // each bucket filled in order of the input: a counting sort, with the starts as cursors that
  // are moved back afterwards
  points_.resize(static_cast<std::size_t>(n));
  for (Eigen::Index j = 0; j < n; ++j) {
    int& slot = start_[static_cast<std::size_t>(bucket_of_[static_cast<std::size_t>(j)])];
    points_[static_cast<std::size_t>(slot++)] = static_cast<int>(j);
  }
  for (std::size_t b = start_.size() - 1; b > 0; --b) start_[b] = start_[b - 1];
  start_[0] = 0;
}

double BucketGrid::SideFor(const Eigen::Ref<const Eigen::Matrix2Xd>& points, double per_bucket) {
  const Eigen::Index n = points.cols();
  if (n == 0) return 1.0;
  const Eigen::Vector2d extent =
      (points.rowwise().maxCoeff() - points.rowwise().minCoeff()).cwiseMax(1e-3);
  return std::max(1e-3, std::sqrt(per_bucket * extent.prod() / static_cast<double>(n)));
}

Eigen::Vector2i BucketGrid::BucketOf(const Eigen::Vector2d& p) const {
  // clamped before the cast: far points must not overflow an int
  const Eigen::Array2d cell = ((p - origin_) / bucket_size_).array().floor();
  return cell.max(0.0).min((count_.array() - 1).cast<double>()).cast<int>();
}

}  // namespace trav::mapping
