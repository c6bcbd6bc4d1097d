#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "common/random.h"
#include "common/scratch.h"
#include "mapping/bucket_grid.h"
#include "mapping/fsgp_config.h"

namespace trav::mapping {

/// The GP's training set: points with their local geometric features. Views into the storage of
/// the TrainingSetExtractor that made it, valid until its next Extract.
struct TrainingSet {
  common::ScratchMatrix<double, 3>::ConstView points_W;  ///< [m]
  /// kappa = lambda_min / (sum lambda + eps) of the k-neighbourhood
  common::ScratchMatrix<double, Eigen::Dynamic, 1>::ConstView curvature;
  /// g = mean |z_j - z_i| over the k neighbours [m]
  common::ScratchMatrix<double, Eigen::Dynamic, 1>::ConstView gradient;
  int pre_voxel_points{0};  ///< after the pre-downsampling
  int feature_points{0};    ///< kappa > tau_kappa or g > tau_g
};

/// Steps 2-3 of FSGP: voxel pre-downsampling (voxel centroids), k nearest neighbours in 3-D,
/// curvature and gradient per point, feature points kept whole, the rest voxel-downsampled (one
/// point per voxel, keeping its own kappa and g: the released code zeroes them), and seeded random
/// sampling down to M points, features first but at most half of M when enough other points remain
/// (the released code samples all alike, which thins out exactly the points that carry structure;
/// taking features only would leave the ground uncovered next to walls). Deterministic for a given
/// `random` state.
///
/// Written here rather than with PCL's VoxelGrid and kd-tree: those allocate their index vectors
/// and tree on every frame and need the cloud copied into PCL's point type, while this extractor
/// reuses its storage (no allocation once its sizes have been seen) and shares the bucket grid of
/// the rest of the mapper.
class TrainingSetExtractor {
 public:
  /// The training set of `points_W` (one point per column). A voxel size <= 0 keeps every point.
  TrainingSet Extract(const Eigen::Ref<const Eigen::Matrix3Xf>& points_W, const FsgpConfig& config,
                      common::Random* random);

  /// Extract in two halves. The first: the voxel centroids of `points_W` and their features, which
  /// depend on the config's pre_voxel_m and neighbours alone.
  void ComputeFeatures(const Eigen::Ref<const Eigen::Matrix3Xf>& points_W,
                       const FsgpConfig& config);
  /// The second: the training set of the features that `featured` (this extractor or another)
  /// computed last, sampled to config.max_training_points with `random`; views into this
  /// extractor's storage. What lets extractors of several M share one ComputeFeatures: the same
  /// training sets, bit for bit, as each one's Extract, if the first half's config is the same.
  TrainingSet SelectFrom(const TrainingSetExtractor& featured, const FsgpConfig& config,
                         common::Random* random);

 private:
  // A point's voxel (integer coordinates) and the point's index, ordered by voxel z, y, x (the
  // order PCL's VoxelGrid gives its centroids), then index.
  struct VoxelEntry {
    std::int64_t x, y, z;
    int index;
    bool operator<(const VoxelEntry& o) const {
      return z != o.z ? z < o.z : y != o.y ? y < o.y : x != o.x ? x < o.x : index < o.index;
    }
    bool SameVoxel(const VoxelEntry& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  // The voxel of `p` for voxels of side 1 / inverse_voxel (<= 0: every point its own voxel).
  template <typename Scalar>
  static VoxelEntry EntryOf(const Eigen::Matrix<Scalar, 3, 1>& p, Scalar inverse_voxel, int index);

  // Voxel centroids of `points_W` into points_W_ (ordered by voxel).
  void Downsample(const Eigen::Ref<const Eigen::Matrix3Xf>& points_W, double voxel_m);
  // Curvature and gradient of every centroid over its k nearest neighbours.
  void ComputeCentroidFeatures(int neighbours);
  // The indices of `featured`'s training points in selected_ (ascending); returns the feature
  // points.
  int SelectTrainingPoints(const TrainingSetExtractor& featured, const FsgpConfig& config,
                           common::Random* random);

  std::vector<VoxelEntry> voxels_;
  common::ScratchMatrix<double, 3> points_W_;  // after the pre-downsampling
  common::ScratchMatrix<double, Eigen::Dynamic, 1> curvature_, gradient_;
  BucketGrid buckets_;
  std::vector<BucketGrid::Neighbour> neighbours_;
  std::vector<int> features_, rest_, selected_;
  common::ScratchMatrix<double, 3> training_W_;
  common::ScratchMatrix<double, Eigen::Dynamic, 1> training_curvature_, training_gradient_;
};

/// Inverse-distance weights (1 / (d + 1e-6), normalised) of the K nearest training points in
/// (x, y) for every query, with the distance to the nearest (BucketGrid::KNearest; ties go to the
/// lower index). A query with no training point within `support_radius_m` gets nearest +infinity,
/// indices -1 and weights 0: its search stops at that radius, which spares the empty parts of a
/// window a search across it. Reuses its storage between calls.
class InverseDistanceWeighting {
 public:
  /// Weights of `training_W` (one point per column; z unused) at every column of `queries_W`.
  void Compute(const Eigen::Ref<const Eigen::Matrix3Xd>& training_W,
               const Eigen::Ref<const Eigen::Matrix2Xd>& queries_W, int k, double support_radius_m);

  /// min(K, training points) x queries: the neighbours' indices (-1: none).
  common::ScratchMatrix<int>::ConstView indices() const { return indices_.view(); }
  /// min(K, training points) x queries: their weights, summing to 1 per supported query.
  common::ScratchMatrix<double>::ConstView weights() const { return weights_.view(); }
  /// Per query, the distance to the nearest training point [m] (+infinity: unsupported).
  common::ScratchMatrix<double, Eigen::Dynamic, 1>::ConstView nearest_m() const {
    return nearest_m_.view();
  }

 private:
  BucketGrid buckets_;
  std::vector<BucketGrid::Neighbour> found_;
  common::ScratchMatrix<int> indices_;
  common::ScratchMatrix<double> weights_;
  common::ScratchMatrix<double, Eigen::Dynamic, 1> nearest_m_;
};

}  // namespace trav::mapping
