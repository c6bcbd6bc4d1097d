#include "mapping/features.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

#include <Eigen/Eigenvalues>
#include <pcl/filters/voxel_grid.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "mapping/bucket_grid.h"

namespace trav::mapping {
namespace {

std::int64_t VoxelKey(const Eigen::Vector3d& p, double voxel) {
  const auto ix = static_cast<std::int64_t>(std::floor(p.x() / voxel)) & 0x1FFFFF;
  const auto iy = static_cast<std::int64_t>(std::floor(p.y() / voxel)) & 0x1FFFFF;
  const auto iz = static_cast<std::int64_t>(std::floor(p.z() / voxel)) & 0x1FFFFF;
  return (ix << 42) | (iy << 21) | iz;
}

// Every point of the voxel-downsampled cloud with its features: the covariance eigenvalue ratio
// (curvature) and the mean height difference (gradient) over its k nearest neighbours.
TrainingSet PointsWithFeatures(const Eigen::Matrix3Xf& points_W, const FsgpConfig& config) {
  // voxel pre-downsampling (voxel centroids)
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->resize(static_cast<std::size_t>(points_W.cols()));
  for (Eigen::Index i = 0; i < points_W.cols(); ++i) {
    (*cloud)[static_cast<std::size_t>(i)] =
        pcl::PointXYZ(points_W(0, i), points_W(1, i), points_W(2, i));
  }
  pcl::PointCloud<pcl::PointXYZ>::Ptr voxelised(new pcl::PointCloud<pcl::PointXYZ>);
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setInputCloud(cloud);
  const float leaf = static_cast<float>(config.pre_voxel_m);
  grid.setLeafSize(leaf, leaf, leaf);
  grid.filter(*voxelised);
  const int n = static_cast<int>(voxelised->size());

  TrainingSet all;
  all.pre_voxel_points = n;
  all.points_W.resize(3, n);
  all.curvature.resize(n);
  all.gradient.resize(n);
  if (n == 0) return all;

  // k nearest neighbours (the point itself included), covariance eigenvalues, height differences
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(voxelised);
  const int k = std::min(config.neighbours, n);
  std::vector<int> indices(static_cast<std::size_t>(k));
  std::vector<float> distances(static_cast<std::size_t>(k));
  for (int i = 0; i < n; ++i) {
    const pcl::PointXYZ& p = (*voxelised)[static_cast<std::size_t>(i)];
    all.points_W.col(i) = Eigen::Vector3d(p.x, p.y, p.z);
    tree.nearestKSearch(p, k, indices, distances);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    double height_differences = 0.0;
    for (int j : indices) {
      const pcl::PointXYZ& q = (*voxelised)[static_cast<std::size_t>(j)];
      mean += Eigen::Vector3d(q.x, q.y, q.z);
      height_differences += std::abs(static_cast<double>(q.z) - p.z);
    }
    mean /= k;
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (int j : indices) {
      const pcl::PointXYZ& q = (*voxelised)[static_cast<std::size_t>(j)];
      const Eigen::Vector3d d = Eigen::Vector3d(q.x, q.y, q.z) - mean;
      covariance += d * d.transpose();
    }
    covariance /= std::max(1, k - 1);
    // closed form (Eigen's computeDirect): a 3 x 3 needs no QR iterations
    const Eigen::Vector3d eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>()
                                            .computeDirect(covariance, Eigen::EigenvaluesOnly)
                                            .eigenvalues();
    all.curvature[i] = std::max(0.0, eigenvalues[0]) / (eigenvalues.sum() + 1e-6);
    all.gradient[i] = height_differences / k;
  }

  return all;
}

// The indices of the training points of `all`, in order: the feature points whole and the others
// one per voxel, sampled down to max_training_points (seeded). Sets all->feature_points.
std::vector<int> SelectTrainingPoints(TrainingSet* all_points, const FsgpConfig& config,
                                      common::Random* random) {
  TrainingSet& all = *all_points;
  const int n = static_cast<int>(all.points_W.cols());
  // feature points whole; the others one per voxel (the first in order, keeping its features)
  std::vector<int> features, rest;
  std::unordered_map<std::int64_t, int> voxel_owner;
  for (int i = 0; i < n; ++i) {
    if (all.curvature[i] > config.curvature_threshold ||
        all.gradient[i] > config.gradient_threshold_m) {
      features.push_back(i);
    } else if (voxel_owner.emplace(VoxelKey(all.points_W.col(i), config.feature_voxel_m), i)
                   .second) {
      rest.push_back(i);
    }
  }
  all.feature_points = static_cast<int>(features.size());
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
  sample(&features, std::max(budget / 2, budget - std::min(budget, rest.size())));
  sample(&rest, budget - features.size());
  std::vector<int> selected = features;
  selected.insert(selected.end(), rest.begin(), rest.end());
  std::sort(selected.begin(), selected.end());

  return selected;
}

}  // namespace

TrainingSet ExtractTrainingSet(const Eigen::Matrix3Xf& points_W, const FsgpConfig& config,
                               common::Random* random) {
  TrainingSet all = PointsWithFeatures(points_W, config);
  if (all.points_W.cols() == 0) return all;
  const std::vector<int> selected = SelectTrainingPoints(&all, config, random);
  TrainingSet training;
  training.pre_voxel_points = all.pre_voxel_points;
  training.feature_points = all.feature_points;
  const auto m = static_cast<Eigen::Index>(selected.size());
  training.points_W.resize(3, m);
  training.curvature.resize(m);
  training.gradient.resize(m);
  for (Eigen::Index s = 0; s < m; ++s) {
    const int i = selected[static_cast<std::size_t>(s)];
    training.points_W.col(s) = all.points_W.col(i);
    training.curvature[s] = all.curvature[i];
    training.gradient[s] = all.gradient[i];
  }
  return training;
}

void InverseDistanceWeights(const Eigen::Matrix3Xd& training_W, const Eigen::Matrix2Xd& queries_W,
                            int k, double support_radius_m, Eigen::MatrixXi* indices,
                            Eigen::MatrixXd* weights, Eigen::VectorXd* nearest_m) {
  // the training points in square buckets of about two points each; a query searches rings of
  // buckets outwards until the ring cannot hold anything closer than its K-th neighbour (a kd-tree
  // costs more to build and query at a few hundred points)
  const Eigen::Index m = training_W.cols();
  const int kk = static_cast<int>(std::min<Eigen::Index>(k, m));
  indices->setConstant(kk, queries_W.cols(), -1);
  weights->setZero(kk, queries_W.cols());
  nearest_m->setConstant(queries_W.cols(), std::numeric_limits<double>::infinity());
  if (kk == 0) return;
  const Eigen::Matrix2Xd training_xy = training_W.topRows<2>();
  const Eigen::Vector2d extent =
      (training_xy.rowwise().maxCoeff() - training_xy.rowwise().minCoeff()).cwiseMax(1e-3);
  const BucketGrid buckets(training_xy,
                           std::max(1e-3, std::sqrt(2.0 * extent.prod() / static_cast<double>(m))));
  const double bucket = buckets.bucket_size();
  const Eigen::Vector2d& low = buckets.origin();
  const int max_ring = buckets.count().sum();  // rings beyond this hold nothing

  // the kk nearest so far, sorted by (distance, index)
  std::vector<std::pair<double, int>> found;
  found.reserve(static_cast<std::size_t>(kk) + 1);
  auto visit_bucket = [&](int bx, int by, const Eigen::Vector2d& p) {
    buckets.ForPointsIn(Eigen::Vector2i(bx, by), [&](int j) {
      const std::pair<double, int> candidate((training_xy.col(j) - p).norm(), j);
      if (static_cast<int>(found.size()) == kk && !(candidate < found.back())) return;
      found.insert(std::upper_bound(found.begin(), found.end(), candidate), candidate);
      if (static_cast<int>(found.size()) > kk) found.pop_back();
    });
  };
  for (Eigen::Index q = 0; q < queries_W.cols(); ++q) {
    const Eigen::Vector2d p = queries_W.col(q);
    const Eigen::Vector2i centre = buckets.BucketOf(p);
    const int qx = centre.x(), qy = centre.y();
    // distance from the query to the outside of its bucket neighbourhood of `ring` rings
    const double inside_x =
        std::min(p.x() - (low.x() + qx * bucket), low.x() + (qx + 1) * bucket - p.x());
    const double inside_y =
        std::min(p.y() - (low.y() + qy * bucket), low.y() + (qy + 1) * bucket - p.y());
    const double inside = std::max(0.0, std::min(inside_x, inside_y));
    found.clear();
    for (int ring = 0;; ++ring) {
      if (ring == 0) {
        visit_bucket(qx, qy, p);
      } else {  // the ring's perimeter: top and bottom rows, then the sides between them
        for (int bx = qx - ring; bx <= qx + ring; ++bx) {
          visit_bucket(bx, qy - ring, p);
          visit_bucket(bx, qy + ring, p);
        }
        for (int by = qy - ring + 1; by <= qy + ring - 1; ++by) {
          visit_bucket(qx - ring, by, p);
          visit_bucket(qx + ring, by, p);
        }
      }
      // every point beyond this ring is at least `reach` away
      const double reach = inside + ring * bucket;
      const bool covered = ring >= max_ring;
      const bool complete = static_cast<int>(found.size()) == kk && found.back().first <= reach;
      const bool unsupported =
          reach > support_radius_m && (found.empty() || found.front().first > support_radius_m);
      if (covered || complete || unsupported) break;
    }
    if (found.empty() || found.front().first > support_radius_m) continue;
    double total = 0.0;
    for (int j = 0; j < kk; ++j) {
      (*indices)(j, q) = found[static_cast<std::size_t>(j)].second;
      (*weights)(j, q) = 1.0 / (found[static_cast<std::size_t>(j)].first + 1e-6);
      total += (*weights)(j, q);
    }
    weights->col(q) /= total;
    (*nearest_m)[q] = found[0].first;
  }
}

}  // namespace trav::mapping
