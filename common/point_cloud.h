#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace trav::common {

/// A point cloud as a structure of arrays: one point per column of `points` [m], expressed in the
/// frame named by `frame_id` ("W", "L", ...). Optional per-point arrays are either empty or have
/// one entry per point.
struct PointCloud {
  Eigen::Matrix3Xf points;       ///< [m], one point per column
  Eigen::VectorXf time_offsets;  ///< per-point time after `stamp_s` [s]; empty if not measured
  Eigen::VectorXi line_ids;      ///< per-point laser line; empty if not applicable
  /// Per-point reflectivity on Livox's scale (0 to 150: diffuse reflectance 0 to 100 %; 151 to
  /// 255: retro-reflectors); empty if not measured.
  Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 1> reflectivity;
  /// Per-point Livox tag (0: a normal point of the first return); empty if not measured.
  Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 1> tags;
  double stamp_s{0.0};        ///< time of the frame [s]
  std::string frame_id{"W"};  ///< frame the points are expressed in

  /// Number of points.
  Eigen::Index size() const { return points.cols(); }
};

/// A cloud of `points` (no per-point arrays) in frame `frame_id`.
inline PointCloud MakePointCloud(const std::vector<Eigen::Vector3f>& points,
                                 const std::string& frame_id = "W") {
  PointCloud cloud;
  cloud.frame_id = frame_id;
  cloud.points.resize(3, static_cast<Eigen::Index>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i) {
    cloud.points.col(static_cast<Eigen::Index>(i)) = points[i];
  }
  return cloud;
}

}  // namespace trav::common
