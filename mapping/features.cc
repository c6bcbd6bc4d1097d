#include "mapping/features.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

namespace trav::mapping {

template <typename Scalar>
TrainingSetExtractor::VoxelEntry TrainingSetExtractor::EntryOf(const Eigen::Matrix<Scalar, 3, 1>& p,
                                                               Scalar inverse_voxel, int index) {
  if (!(inverse_voxel > 0) || !std::isfinite(inverse_voxel)) return {index, 0, 0, index};
  // clamped before the cast: a far point must not overflow
  const Eigen::Array3d c =
      (p * inverse_voxel).array().floor().template cast<double>().max(-4e18).min(4e18);
  return {static_cast<std::int64_t>(c.x()), static_cast<std::int64_t>(c.y()),
          static_cast<std::int64_t>(c.z()), index};
}

void TrainingSetExtractor::Downsample(const Eigen::Ref<const Eigen::Matrix3Xf>& points_W,
                                      double voxel_m) {
  // in single precision as PCL's VoxelGrid does (points on a voxel boundary fall alike)
  const float inverse_voxel = voxel_m > 0.0 ? 1.0f / static_cast<float>(voxel_m) : 0.0f;
  voxels_.clear();
  for (Eigen::Index i = 0; i < points_W.cols(); ++i)
    voxels_.push_back(EntryOf<float>(points_W.col(i), inverse_voxel, static_cast<int>(i)));
  std::sort(voxels_.begin(), voxels_.end());
  std::size_t count = 0;
  for (std::size_t i = 0; i < voxels_.size(); ++i)
    count += (i == 0 || !voxels_[i].SameVoxel(voxels_[i - 1])) ? 1 : 0;
  auto centroids = points_W_.Resize(3, static_cast<Eigen::Index>(count));
  // each voxel's points are consecutive: their mean, summed in single precision in the order of
  // the input
  Eigen::Index at = 0;
  for (std::size_t first = 0; first < voxels_.size();) {
    std::size_t last = first + 1;
    while (last < voxels_.size() && voxels_[last].SameVoxel(voxels_[first])) ++last;
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    for (std::size_t i = first; i < last; ++i) sum += points_W.col(voxels_[i].index);
    centroids.col(at++) = (sum / static_cast<float>(last - first)).cast<double>();
    first = last;
  }
}

void TrainingSetExtractor::ComputeCentroidFeatures(int neighbours) {
  const auto points = points_W_.view();
  const Eigen::Index n = points.cols();
  auto curvature = curvature_.Resize(n);
  auto gradient = gradient_.Resize(n);
  if (n == 0) return;
  // about one neighbourhood in the 3 x 3 buckets around a point on open ground (a quarter of one
  // per bucket, as before, put 2.25 there: features 6 to 8 % slower, mapping_benchmark)
  buckets_.Rebuild(points.topRows<2>(), BucketGrid::SideFor(points.topRows<2>(), neighbours / 9.0));
  const int k = static_cast<int>(std::min<Eigen::Index>(neighbours, n));
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d p = points.col(i);
    // k nearest in 3-D (the point itself included): never nearer than in the plane; by squared
    // distance, as only the neighbours are used
    buckets_.KNearest<true>(
        p.head<2>(), k, std::numeric_limits<double>::infinity(),
        [&](int j) { return (points.col(j) - p).squaredNorm(); }, &neighbours_);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    double height_differences = 0.0;
    for (const BucketGrid::Neighbour& neighbour : neighbours_) {
      const Eigen::Vector3d q = points.col(neighbour.second);
      mean += q;
      height_differences += std::abs(q.z() - p.z());
    }
    mean /= k;
    // the six distinct sums of the outer products d d^T, each the same products and additions
    // as Eigen's `covariance += d * d.transpose()` (whose 3 x 3 temporary went through the stack
    // on every neighbour: the features' hottest loop)
    double xx = 0.0, xy = 0.0, xz = 0.0, yy = 0.0, yz = 0.0, zz = 0.0;
    for (const BucketGrid::Neighbour& neighbour : neighbours_) {
      const Eigen::Vector3d d = points.col(neighbour.second) - mean;
      xx += d.x() * d.x();
      xy += d.x() * d.y();
      xz += d.x() * d.z();
      yy += d.y() * d.y();
      yz += d.y() * d.z();
      zz += d.z() * d.z();
    }
    Eigen::Matrix3d covariance;
    covariance << xx, xy, xz, xy, yy, yz, xz, yz, zz;
    covariance /= std::max(1, k - 1);
    // closed form (Eigen's computeDirect): a 3 x 3 needs no QR iterations
    const Eigen::Vector3d eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>()
                                            .computeDirect(covariance, Eigen::EigenvaluesOnly)
                                            .eigenvalues();
    curvature[i] = std::max(0.0, eigenvalues[0]) / (eigenvalues.sum() + 1e-6);
    gradient[i] = height_differences / k;
  }
}

int TrainingSetExtractor::SelectTrainingPoints(const TrainingSetExtractor& featured,
                                               const FsgpConfig& config, common::Random* random) {
  const auto points = featured.points_W_.view();
  const auto curvature = featured.curvature_.view();
  const auto gradient = featured.gradient_.view();
  const Eigen::Index n = points.cols();
  // feature points whole; the others one per voxel (the first in order, keeping its features)
  features_.clear();
  rest_.clear();
  voxels_.clear();
  for (Eigen::Index i = 0; i < n; ++i) {
    if (curvature[i] > config.curvature_threshold || gradient[i] > config.gradient_threshold_m) {
      features_.push_back(static_cast<int>(i));
    } else {
      voxels_.push_back(EntryOf<double>(
          points.col(i), config.feature_voxel_m > 0.0 ? 1.0 / config.feature_voxel_m : 0.0,
          static_cast<int>(i)));
    }
  }
  std::sort(voxels_.begin(), voxels_.end());
  for (std::size_t i = 0; i < voxels_.size(); ++i) {
    if (i == 0 || !voxels_[i].SameVoxel(voxels_[i - 1])) rest_.push_back(voxels_[i].index);
  }
  std::sort(rest_.begin(), rest_.end());
  const int feature_points = static_cast<int>(features_.size());
  // seeded sampling down to M, features first: the random cap must not thin out the few points
  // that carry the terrain's structure
  auto sample = [&](std::vector<int>* from, std::size_t count) {
    for (std::size_t i = 0; i < count && i < from->size(); ++i) {
      const std::size_t j = i + random->UniformIndex(static_cast<std::uint64_t>(from->size() - i));
      std::swap((*from)[i], (*from)[j]);
    }
    from->resize(std::min(count, from->size()));
  };
  const auto budget = static_cast<std::size_t>(config.max_training_points);
  // features take at most half of the budget when there are enough other points: the rest keeps
  // the ground covered (indoors, wall points alone would otherwise fill M)
  sample(&features_, std::max(budget / 2, budget - std::min(budget, rest_.size())));
  sample(&rest_, budget - features_.size());
  selected_.assign(features_.begin(), features_.end());
  selected_.insert(selected_.end(), rest_.begin(), rest_.end());
  std::sort(selected_.begin(), selected_.end());
  return feature_points;
}

TrainingSet TrainingSetExtractor::Extract(const Eigen::Ref<const Eigen::Matrix3Xf>& points_W,
                                          const FsgpConfig& config, common::Random* random) {
  ComputeFeatures(points_W, config);
  return SelectFrom(*this, config, random);
}

void TrainingSetExtractor::ComputeFeatures(const Eigen::Ref<const Eigen::Matrix3Xf>& points_W,
                                           const FsgpConfig& config) {
  Downsample(points_W, config.pre_voxel_m);
  ComputeCentroidFeatures(config.neighbours);
}

TrainingSet TrainingSetExtractor::SelectFrom(const TrainingSetExtractor& featured,
                                             const FsgpConfig& config, common::Random* random) {
  const auto points_W = featured.points_W_.view();
  const auto pre_voxel_points = static_cast<int>(points_W.cols());
  selected_.clear();
  const int feature_points =
      pre_voxel_points > 0 ? SelectTrainingPoints(featured, config, random) : 0;
  const auto m = static_cast<Eigen::Index>(selected_.size());
  auto training_W = training_W_.Resize(3, m);
  auto curvature = training_curvature_.Resize(m);
  auto gradient = training_gradient_.Resize(m);
  for (Eigen::Index s = 0; s < m; ++s) {
    const int i = selected_[static_cast<std::size_t>(s)];
    training_W.col(s) = points_W.col(i);
    curvature[s] = featured.curvature_.view()[i];
    gradient[s] = featured.gradient_.view()[i];
  }
  return {training_W_.const_view(), training_curvature_.const_view(),
          training_gradient_.const_view(), pre_voxel_points, feature_points};
}

void InverseDistanceWeighting::Compute(const Eigen::Ref<const Eigen::Matrix3Xd>& training_W,
                                       const Eigen::Ref<const Eigen::Matrix2Xd>& queries_W, int k,
                                       double support_radius_m) {
  // the training points in square buckets of about two points each
  const Eigen::Index m = training_W.cols();
  const int kk = static_cast<int>(std::min<Eigen::Index>(k, m));
  auto indices = indices_.Resize(kk, queries_W.cols());
  auto weights = weights_.Resize(kk, queries_W.cols());
  auto nearest_m = nearest_m_.Resize(queries_W.cols());
  indices.setConstant(-1);
  weights.setZero();
  nearest_m.setConstant(std::numeric_limits<double>::infinity());
  if (kk == 0) return;
  const auto training_xy = training_W.topRows<2>();
  buckets_.Rebuild(training_xy, BucketGrid::SideFor(training_xy, 2.0));
  for (Eigen::Index q = 0; q < queries_W.cols(); ++q) {
    const Eigen::Vector2d p = queries_W.col(q);
    // by squared distance, the square root taken of the k found only (the same values: Eigen's
    // norm is the square root of squaredNorm)
    buckets_.KNearest<true>(
        p, kk, support_radius_m, [&](int j) { return (training_xy.col(j) - p).squaredNorm(); },
        &found_);
    if (found_.empty()) continue;
    const double first_m = std::sqrt(found_.front().first);
    if (first_m > support_radius_m) continue;
    double total = 0.0;
    for (int j = 0; j < kk; ++j) {
      const auto& [squared_m2, index] = found_[static_cast<std::size_t>(j)];
      indices(j, q) = index;
      weights(j, q) = 1.0 / (std::sqrt(squared_m2) + 1e-6);
      total += weights(j, q);
    }
    weights.col(q) /= total;
    nearest_m[q] = first_m;
  }
}

}  // namespace trav::mapping
