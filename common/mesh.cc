#include "common/mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>

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

// The interval of t where a t^2 + b t + c <= 0 (a >= 0), intersected with [low, high]; false if
// empty.
bool QuadraticInterval(double a, double b, double c, double* low, double* high) {
  constexpr double kParallel = 1e-12;
  if (a < kParallel) {
    // the line runs along the quadric's axis: inside everywhere or nowhere (b is 0 then)
    return c <= 0.0;
  }
  const double discriminant = b * b - 4.0 * a * c;
  if (discriminant < 0.0) return false;
  const double root = std::sqrt(discriminant);
  *low = std::max(*low, (-b - root) / (2.0 * a));
  *high = std::min(*high, (-b + root) / (2.0 * a));
  return *low <= *high;
}

// The parameters where the line p + t d (in the shape's frame) is inside a sphere of `radius`
// centred on `centre`, intersected with [low, high].
bool SphereInterval(const Eigen::Vector3d& p, const Eigen::Vector3d& d,
                    const Eigen::Vector3d& centre, double radius, double* low, double* high) {
  const Eigen::Vector3d q = p - centre;
  return QuadraticInterval(d.squaredNorm(), 2.0 * q.dot(d), q.squaredNorm() - radius * radius, low,
                           high);
}

// ... inside the infinite cylinder of `radius` about the local z axis, and between z = -half and
// z = half.
bool CylinderInterval(const Eigen::Vector3d& p, const Eigen::Vector3d& d, double radius,
                      double half, double* low, double* high) {
  if (!QuadraticInterval(d.x() * d.x() + d.y() * d.y(), 2.0 * (p.x() * d.x() + p.y() * d.y()),
                         p.x() * p.x() + p.y() * p.y() - radius * radius, low, high)) {
    return false;
  }
  constexpr double kParallel = 1e-12;
  if (std::abs(d.z()) < kParallel) return std::abs(p.z()) <= half;
  const double t1 = (-half - p.z()) / d.z(), t2 = (half - p.z()) / d.z();
  *low = std::max(*low, std::min(t1, t2));
  *high = std::min(*high, std::max(t1, t2));
  return *low <= *high;
}

}  // namespace

std::optional<std::pair<double, double>> VerticalExtent(const Primitive& primitive,
                                                        const Eigen::Vector2d& p_W) {
  // the line (x, y, 0) + t e_z of W in the shape's frame O: its points are at height t in W
  const Eigen::Matrix3d R_OW = primitive.X_WO.linear().transpose();
  const Eigen::Vector3d p =
      R_OW * (Eigen::Vector3d(p_W.x(), p_W.y(), 0.0) - primitive.X_WO.translation());
  const Eigen::Vector3d d = R_OW.col(2);
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  double low = -kInfinity, high = kInfinity;
  const Eigen::Vector3d& size = primitive.size;
  bool hit = false;
  switch (primitive.shape) {
    case ShapeType::kBox: {
      hit = true;
      for (int i = 0; i < 3 && hit; ++i) {
        if (std::abs(d[i]) < 1e-12) {
          hit = std::abs(p[i]) <= size[i];
          continue;
        }
        const double t1 = (-size[i] - p[i]) / d[i], t2 = (size[i] - p[i]) / d[i];
        low = std::max(low, std::min(t1, t2));
        high = std::min(high, std::max(t1, t2));
        hit = low <= high;
      }
      break;
    }
    case ShapeType::kSphere:
      hit = SphereInterval(p, d, Eigen::Vector3d::Zero(), size[0], &low, &high);
      break;
    case ShapeType::kCylinder:
      hit = CylinderInterval(p, d, size[0], size[1], &low, &high);
      break;
    case ShapeType::kCapsule: {
      // convex: the union of its cylinder's and its two spheres' intervals is one interval
      double part_low[3], part_high[3];
      bool part_hit[3];
      for (int k = 0; k < 3; ++k) {
        part_low[k] = -kInfinity;
        part_high[k] = kInfinity;
      }
      part_hit[0] = CylinderInterval(p, d, size[0], size[1], &part_low[0], &part_high[0]);
      part_hit[1] = SphereInterval(p, d, Eigen::Vector3d(0, 0, size[1]), size[0], &part_low[1],
                                   &part_high[1]);
      part_hit[2] = SphereInterval(p, d, Eigen::Vector3d(0, 0, -size[1]), size[0], &part_low[2],
                                   &part_high[2]);
      low = kInfinity;
      high = -kInfinity;
      for (int k = 0; k < 3; ++k) {
        if (!part_hit[k]) continue;
        hit = true;
        low = std::min(low, part_low[k]);
        high = std::max(high, part_high[k]);
      }
      break;
    }
  }
  if (!hit || !std::isfinite(low) || !std::isfinite(high)) return std::nullopt;
  return std::make_pair(low, high);
}

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
  ForEachSurfaceSample(mesh, spacing_m, [&](const Eigen::Vector3f& p) { points.push_back(p); });
  return MakePointCloud(points);
}

}  // namespace trav::common
