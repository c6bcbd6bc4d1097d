#pragma once

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "common/point_cloud.h"

namespace trav::common {

/// Primitive shapes.
enum class ShapeType { kBox, kCylinder, kSphere, kCapsule };

/// A primitive solid. Sizes follow MuJoCo's conventions: box half-extents (x, y, z); cylinder and
/// capsule (radius, half-length, unused) along the local z axis; sphere (radius, unused, unused).
struct Primitive {
  ShapeType shape{ShapeType::kBox};
  Eigen::Isometry3d X_WO{Eigen::Isometry3d::Identity()};  ///< pose of the shape's frame O in W
  Eigen::Vector3d size{Eigen::Vector3d::Zero()};          ///< [m], see above
};

/// A triangle mesh.
struct TriangleMesh {
  Eigen::Matrix3Xf vertices;   ///< [m], one vertex per column, in the frame the owner names
  Eigen::Matrix3Xi triangles;  ///< vertex indices, counter-clockwise seen from outside
};

/// The surface of a primitive as triangles in W: a box exactly (12 triangles); cylinders, capsules
/// and spheres as surfaces of revolution with `segments` around (>= 3) and a vertex at angle 0 (on
/// the local +x axis) of every ring.
TriangleMesh PrimitiveMesh(const Primitive& primitive, int segments = 16);

/// The heights [m] where the vertical line through p_W (x, y) enters and leaves the primitive's
/// solid (low, high), or nothing if it misses it. Exact for every shape and pose.
std::optional<std::pair<double, double>> VerticalExtent(const Primitive& primitive,
                                                        const Eigen::Vector2d& p_W);

/// Appends `mesh` to `into`.
void AppendMesh(const TriangleMesh& mesh, TriangleMesh* into);

/// Calls visit(point) for the points on the surface of `mesh`, on a lattice of every triangle with
/// at most `spacing_m` between neighbours, in the mesh's frame (triangle by triangle, in order).
template <typename Visit>
void ForEachSurfaceSample(const TriangleMesh& mesh, double spacing_m, Visit visit) {
  for (Eigen::Index t = 0; t < mesh.triangles.cols(); ++t) {
    const Eigen::Vector3f a = mesh.vertices.col(mesh.triangles(0, t));
    const Eigen::Vector3f b = mesh.vertices.col(mesh.triangles(1, t));
    const Eigen::Vector3f c = mesh.vertices.col(mesh.triangles(2, t));
    // a lattice along the two edges from a, each divided finely enough for the spacing
    const int n_u = std::max(1, static_cast<int>(std::ceil((b - a).norm() / spacing_m)));
    const int n_v = std::max(1, static_cast<int>(std::ceil((c - a).norm() / spacing_m)));
    for (int i = 0; i <= n_u; ++i) {
      const float u = static_cast<float>(i) / static_cast<float>(n_u);
      for (int j = 0; j <= n_v; ++j) {
        const float v = static_cast<float>(j) / static_cast<float>(n_v);
        if (u + v > 1.0f + 1e-6f) break;
        visit(Eigen::Vector3f(a + u * (b - a) + v * (c - a)));
      }
    }
  }
}

/// The points of ForEachSurfaceSample as a cloud.
PointCloud SampleSurface(const TriangleMesh& mesh, double spacing_m);

}  // namespace trav::common
