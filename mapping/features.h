#pragma once

#include <Eigen/Core>

#include "common/random.h"
#include "mapping/fsgp_config.h"

namespace trav::mapping {

/// The GP's training set: points with their local geometric features.
struct TrainingSet {
  Eigen::Matrix3Xd points_W;  ///< [m]
  Eigen::VectorXd curvature;  ///< kappa = lambda_min / (sum lambda + eps) of the k-neighbourhood
  Eigen::VectorXd gradient;   ///< g = mean |z_j - z_i| over the k neighbours [m]
  int pre_voxel_points{0};    ///< after the pre-downsampling
  int feature_points{0};      ///< kappa > tau_kappa or g > tau_g
};

/// Steps 2-3 of FSGP: voxel pre-downsampling (PCL), k-nearest neighbours (PCL kd-tree), curvature
/// and gradient per point, feature points kept whole, the rest voxel-downsampled (one point per
/// voxel, keeping its own kappa and g: the released code zeroes them), and seeded random sampling
/// down to M points, features first but at most half of M when enough other points remain (the
/// released code samples all alike, which thins out exactly the points that carry structure; taking
/// features only would leave the ground uncovered next to walls). Deterministic for a given
/// `random` state.
TrainingSet ExtractTrainingSet(const Eigen::Matrix3Xf& points_W, const FsgpConfig& config,
                               common::Random* random);

/// Inverse-distance weights (1 / (d + 1e-6), normalised) of the K nearest training points in
/// (x, y) for every query, with the distance to the nearest (buckets searched ring by ring; ties go
/// to the lower index). A query with no training point within `support_radius_m` gets nearest
/// +infinity, indices -1 and weights 0: its search stops at that radius, which spares the empty
/// parts of a window a search across it.
void InverseDistanceWeights(const Eigen::Matrix3Xd& training_W, const Eigen::Matrix2Xd& queries_W,
                            int k, double support_radius_m, Eigen::MatrixXi* indices,
                            Eigen::MatrixXd* weights, Eigen::VectorXd* nearest_m);

}  // namespace trav::mapping
