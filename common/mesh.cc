#include "common/mesh.h"

#include <algorithm>
#include <cmath>

namespace trav::common {
namespace {

// Builds meshes vertex by vertex; converted to Eigen matrices at the end.
struct MeshBuilder {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Eigen::Vector3i> triangles;

  int AddVertex(const Eigen::Vector3d& p) {
    vertices.push_back(p.cast<float>());
    return static_cast<int>(vertices.size()) - 1;
  }
  void AddTriangle(int a, int b, int c) { triangles.emplace_back(a, b, c); }
  void AddQuad(int a, int b, int c, int d) {
    AddTriangle(a, b, c);
    AddTriangle(a, c, d);
  }

  TriangleMesh Finish() const {
    TriangleMesh mesh;
    mesh.vertices.resize(3, static_cast<Eigen::Index>(vertices.size()));
    mesh.triangles.resize(3, static_cast<Eigen::Index>(triangles.size()));
    for (std::size_t i = 0; i < vertices.size(); ++i)
      mesh.vertices.col(static_cast<Eigen::Index>(i)) = vertices[i];
    for (std::size_t i = 0; i < triangles.size(); ++i)
      mesh.triangles.col(static_cast<Eigen::Index>(i)) = triangles[i];
    return mesh;
  }
};

void AddBox(const Primitive& box, MeshBuilder* mesh) {
  int v[8];
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d corner((k & 1 ? 1 : -1) * box.size.x(), (k & 2 ? 1 : -1) * box.size.y(),
                                 (k & 4 ? 1 : -1) * box.size.z());
    v[k] = mesh->AddVertex(box.X_WO * corner);
  }
  // faces counter-clockwise seen from outside
  mesh->AddQuad(v[0], v[2], v[3], v[1]);  // -z
  mesh->AddQuad(v[4], v[5], v[7], v[6]);  // +z
  mesh->AddQuad(v[0], v[1], v[5], v[4]);  // -y
  mesh->AddQuad(v[2], v[6], v[7], v[3]);  // +y
  mesh->AddQuad(v[0], v[4], v[6], v[2]);  // -x
  mesh->AddQuad(v[1], v[3], v[7], v[5]);  // +x
}

// Surface of revolution about the local z axis through `profile` points (radius, z), from the
// bottom pole to the top pole; points with zero radius become single vertices.
void AddLathe(const Eigen::Isometry3d& X_WO, const std::vector<Eigen::Vector2d>& profile,
              int segments, MeshBuilder* mesh) {
  std::vector<std::vector<int>> rings;
  for (const Eigen::Vector2d& point : profile) {
    std::vector<int> ring;
    const int count = point.x() > 0.0 ? segments : 1;
    for (int s = 0; s < count; ++s) {
      const double angle = 2.0 * M_PI * s / segments;
      ring.push_back(
          mesh->AddVertex(X_WO * Eigen::Vector3d(point.x() * std::cos(angle),
                                                 point.x() * std::sin(angle), point.y())));
    }
    rings.push_back(std::move(ring));
  }
  for (std::size_t r = 0; r + 1 < rings.size(); ++r) {
    const std::vector<int>& lower = rings[r];
    const std::vector<int>& upper = rings[r + 1];
    for (int s = 0; s < segments; ++s) {
      const int n = (s + 1) % segments;
      if (lower.size() == 1 && upper.size() == 1) continue;
      if (lower.size() == 1) {
        mesh->AddTriangle(lower[0], upper[n], upper[s]);
      } else if (upper.size() == 1) {
        mesh->AddTriangle(lower[s], lower[n], upper[0]);
      } else {
        mesh->AddQuad(lower[s], lower[n], upper[n], upper[s]);
      }
    }
  }
}

std::vector<Eigen::Vector2d> SphereProfile(double radius, double z_offset, double from, double to,
                                           int steps) {
  std::vector<Eigen::Vector2d> profile;
  for (int k = 0; k <= steps; ++k) {
    const double polar = from + (to - from) * k / steps;  // angle from -z
    profile.emplace_back(radius * std::sin(polar), z_offset - radius * std::cos(polar));
  }
  return profile;
}

}  // namespace

TriangleMesh PrimitiveMesh(const Primitive& primitive, int segments) {
  segments = std::max(segments, 3);
  const int arc_steps = std::max(2, segments / 4);
  MeshBuilder mesh;
  const double r = primitive.size.x();
  const double half = primitive.size.y();
  switch (primitive.shape) {
    case ShapeType::kBox:
      AddBox(primitive, &mesh);
      break;
    case ShapeType::kCylinder:
      AddLathe(primitive.X_WO, {{0, -half}, {r, -half}, {r, half}, {0, half}}, segments, &mesh);
      break;
    case ShapeType::kSphere:
      AddLathe(primitive.X_WO, SphereProfile(r, 0.0, 0.0, M_PI, 2 * arc_steps), segments, &mesh);
      break;
    case ShapeType::kCapsule: {
      std::vector<Eigen::Vector2d> profile = SphereProfile(r, -half, 0.0, M_PI / 2, arc_steps);
      const std::vector<Eigen::Vector2d> top = SphereProfile(r, half, M_PI / 2, M_PI, arc_steps);
      profile.insert(profile.end(), top.begin(), top.end());
      AddLathe(primitive.X_WO, profile, segments, &mesh);
      break;
    }
  }
  return mesh.Finish();
}

void AppendMesh(const TriangleMesh& mesh, TriangleMesh* into) {
  const Eigen::Index vertex_offset = into->vertices.cols();
  const Eigen::Index triangle_offset = into->triangles.cols();
  into->vertices.conservativeResize(3, vertex_offset + mesh.vertices.cols());
  into->vertices.rightCols(mesh.vertices.cols()) = mesh.vertices;
  into->triangles.conservativeResize(3, triangle_offset + mesh.triangles.cols());
  into->triangles.rightCols(mesh.triangles.cols()) =
      mesh.triangles.array() + static_cast<int>(vertex_offset);
}

PointCloud SampleSurface(const TriangleMesh& mesh, double spacing_m) {
  std::vector<Eigen::Vector3f> points;
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
        points.push_back(a + u * (b - a) + v * (c - a));
      }
    }
  }
  return MakePointCloud(points);
}

}  // namespace trav::common
