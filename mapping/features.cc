#include "mapping/features.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Eigenvalues>
#include <pcl/filters/voxel_grid.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

namespace trav::mapping {
namespace {

std::int64_t VoxelKey(const Eigen::Vector3d& p, double voxel) {
  const auto ix = static_cast<std::int64_t>(std::floor(p.x() / voxel)) & 0x1FFFFF;
  const auto iy = static_cast<std::int64_t>(std::floor(p.y() / voxel)) & 0x1FFFFF;
  const auto iz = static_cast<std::int64_t>(std::floor(p.z() / voxel)) & 0x1FFFFF;
  return (ix << 42) | (iy << 21) | iz;
}

}  // namespace

TrainingSet ExtractTrainingSet(const Eigen::Matrix3Xf& points_W, const FsgpConfig& config,
                               common::Random* random) {
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
    const Eigen::Vector3d eigenvalues =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance, Eigen::EigenvaluesOnly)
            .eigenvalues();
    all.curvature[i] = std::max(0.0, eigenvalues[0]) / (eigenvalues.sum() + 1e-6);
    all.gradient[i] = height_differences / k;
  }

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
  sample(&features, budget);
  sample(&rest, budget - features.size());
  std::vector<int> selected = features;
  selected.insert(selected.end(), rest.begin(), rest.end());
  std::sort(selected.begin(), selected.end());

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
                            int k, Eigen::MatrixXi* indices, Eigen::MatrixXd* weights,
                            Eigen::VectorXd* nearest_m) {
  // a 2-D kd-tree: the training points flattened to z = 0
  pcl::PointCloud<pcl::PointXYZ>::Ptr flat(new pcl::PointCloud<pcl::PointXYZ>);
  flat->resize(static_cast<std::size_t>(training_W.cols()));
  for (Eigen::Index j = 0; j < training_W.cols(); ++j) {
    (*flat)[static_cast<std::size_t>(j)] = pcl::PointXYZ(
        static_cast<float>(training_W(0, j)), static_cast<float>(training_W(1, j)), 0.0f);
  }
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(flat);
  const int kk = static_cast<int>(std::min<Eigen::Index>(k, training_W.cols()));
  indices->resize(kk, queries_W.cols());
  weights->resize(kk, queries_W.cols());
  nearest_m->resize(queries_W.cols());
  std::vector<int> found(static_cast<std::size_t>(kk));
  std::vector<float> squared(static_cast<std::size_t>(kk));
  for (Eigen::Index q = 0; q < queries_W.cols(); ++q) {
    const pcl::PointXYZ query(static_cast<float>(queries_W(0, q)),
                              static_cast<float>(queries_W(1, q)), 0.0f);
    tree.nearestKSearch(query, kk, found, squared);
    double total = 0.0;
    for (int j = 0; j < kk; ++j) {
      const double distance = std::sqrt(static_cast<double>(squared[static_cast<std::size_t>(j)]));
      (*indices)(j, q) = found[static_cast<std::size_t>(j)];
      (*weights)(j, q) = 1.0 / (distance + 1e-6);
      total += (*weights)(j, q);
    }
    weights->col(q) /= total;
    (*nearest_m)[q] = std::sqrt(static_cast<double>(squared[0]));
  }
}

}  // namespace trav::mapping
