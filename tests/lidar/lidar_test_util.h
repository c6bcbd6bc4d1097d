#pragma once

#include <Eigen/Geometry>

#include "common/mesh.h"

namespace trav::lidar::testing {

/// A horizontal square of side 2 * half_m at height z_m, as two triangles.
inline common::TriangleMesh Plane(double half_m, double z_m) {
  common::TriangleMesh mesh;
  const float h = static_cast<float>(half_m);
  const float z = static_cast<float>(z_m);
  mesh.vertices.resize(3, 4);
  mesh.vertices << -h, h, h, -h, -h, -h, h, h, z, z, z, z;
  mesh.triangles.resize(3, 2);
  mesh.triangles << 0, 0, 1, 2, 2, 3;
  return mesh;
}

/// A primitive of `shape` with `size` at `p_W`, axis-aligned.
inline common::Primitive MakePrimitive(common::ShapeType shape, const Eigen::Vector3d& size,
                                       const Eigen::Vector3d& p_W) {
  common::Primitive primitive;
  primitive.shape = shape;
  primitive.size = size;
  primitive.X_WO.translation() = p_W;
  return primitive;
}

/// A pose translated to p_W.
inline Eigen::Isometry3d At(const Eigen::Vector3d& p_W) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = p_W;
  return X;
}

}  // namespace trav::lidar::testing
