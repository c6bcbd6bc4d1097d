#include "mapping/bucket_grid.h"

namespace trav::mapping {

BucketGrid::BucketGrid(const Eigen::Ref<const Eigen::Matrix2Xd>& points, double bucket_size)
    : bucket_size_(bucket_size) {
  const Eigen::Index n = points.cols();
  if (n == 0) return;
  origin_ = points.rowwise().minCoeff();
  const Eigen::Vector2d extent = points.rowwise().maxCoeff() - origin_;
  count_ = (extent / bucket_size_).array().floor().cast<int>() + 1;
  std::vector<int> bucket_of(static_cast<std::size_t>(n));
  start_.assign(static_cast<std::size_t>(count_.prod()) + 1, 0);
  for (Eigen::Index j = 0; j < n; ++j) {
    const Eigen::Vector2i b = BucketOf(points.col(j));
    bucket_of[static_cast<std::size_t>(j)] = b.y() * count_.x() + b.x();
    ++start_[static_cast<std::size_t>(bucket_of[static_cast<std::size_t>(j)]) + 1];
  }
  for (std::size_t b = 1; b < start_.size(); ++b) start_[b] += start_[b - 1];
  points_.resize(static_cast<std::size_t>(n));
  std::vector<int> next(start_.begin(), start_.end() - 1);
  for (Eigen::Index j = 0; j < n; ++j) {
    int& slot = next[static_cast<std::size_t>(bucket_of[static_cast<std::size_t>(j)])];
    points_[static_cast<std::size_t>(slot++)] = static_cast<int>(j);
  }
}

Eigen::Vector2i BucketGrid::BucketOf(const Eigen::Vector2d& p) const {
  // clamped before the cast: far points must not overflow an int
  const Eigen::Array2d cell = ((p - origin_) / bucket_size_).array().floor();
  return cell.max(0.0).min((count_.array() - 1).cast<double>()).cast<int>();
}

}  // namespace trav::mapping
