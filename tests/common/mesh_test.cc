#include "common/mesh.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

namespace trav::common {
namespace {

// Brute force: is the point p_W inside the primitive's solid?
bool Inside(const Primitive& primitive, const Eigen::Vector3d& p_W) {
  const Eigen::Vector3d p = primitive.X_WO.inverse() * p_W;
  const Eigen::Vector3d& size = primitive.size;
  switch (primitive.shape) {
    case ShapeType::kBox:
      return (p.cwiseAbs().array() <= size.array()).all();
    case ShapeType::kSphere:
      return p.norm() <= size[0];
    case ShapeType::kCylinder:
      return p.head<2>().norm() <= size[0] && std::abs(p.z()) <= size[1];
    case ShapeType::kCapsule: {
      const double z = std::clamp(p.z(), -size[1], size[1]);
      return (p - Eigen::Vector3d(0, 0, z)).norm() <= size[0];
    }
  }
  return false;
}

TEST(VerticalExtentTest, UprightShapesGiveTheirBottomAndTop) {
  Primitive box;
  box.shape = ShapeType::kBox;
  box.size = Eigen::Vector3d(1.0, 0.5, 0.25);
  box.X_WO.translation() = Eigen::Vector3d(2, 0, 1);
  const auto inside = VerticalExtent(box, Eigen::Vector2d(2.9, 0.4));
  ASSERT_TRUE(inside);
  EXPECT_DOUBLE_EQ(inside->first, 0.75);
  EXPECT_DOUBLE_EQ(inside->second, 1.25);
  EXPECT_FALSE(VerticalExtent(box, Eigen::Vector2d(3.1, 0.0)));
  Primitive sphere;
  sphere.shape = ShapeType::kSphere;
  sphere.size = Eigen::Vector3d(0.5, 0, 0);
  const auto through = VerticalExtent(sphere, Eigen::Vector2d(0.3, 0.0));
  ASSERT_TRUE(through);
  EXPECT_NEAR(through->first, -0.4, 1e-12);
  EXPECT_NEAR(through->second, 0.4, 1e-12);
  Primitive capsule;
  capsule.shape = ShapeType::kCapsule;
  capsule.size = Eigen::Vector3d(0.2, 1.0, 0);
  const auto pill = VerticalExtent(capsule, Eigen::Vector2d(0.0, 0.0));
  ASSERT_TRUE(pill);
  EXPECT_NEAR(pill->first, -1.2, 1e-12);
  EXPECT_NEAR(pill->second, 1.2, 1e-12);
}

TEST(VerticalExtentTest, TiltedShapesMatchABruteForceWalkAlongTheLine) {
  for (const ShapeType shape :
       {ShapeType::kBox, ShapeType::kCylinder, ShapeType::kSphere, ShapeType::kCapsule}) {
    Primitive primitive;
    primitive.shape = shape;
    primitive.size = Eigen::Vector3d(0.4, 0.8, 0.3);
    primitive.X_WO.linear() = (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()))
                                  .toRotationMatrix();
    primitive.X_WO.translation() = Eigen::Vector3d(0.1, -0.2, 1.0);
    for (double x = -1.0; x <= 1.0; x += 0.1) {
      for (double y = -1.0; y <= 1.0; y += 0.1) {
        constexpr double kStep = 1e-3;
        double low = 1e9, high = -1e9;
        for (double z = -2.0; z <= 4.0; z += kStep) {
          if (!Inside(primitive, Eigen::Vector3d(x, y, z))) continue;
          low = std::min(low, z);
          high = std::max(high, z);
        }
        const auto extent = VerticalExtent(primitive, Eigen::Vector2d(x, y));
        if (low > high) {
          // the walk may miss a sliver thinner than its step
          if (extent) {
            EXPECT_LT(extent->second - extent->first, kStep);
          }
          continue;
        }
        ASSERT_TRUE(extent) << static_cast<int>(shape) << " at " << x << ", " << y;
        EXPECT_NEAR(extent->first, low, kStep);
        EXPECT_NEAR(extent->second, high, kStep);
      }
    }
  }
}

TEST(MeshTest, BoxMeshHasTwelveOutwardTrianglesOnItsCorners) {
  Primitive box;
  box.shape = ShapeType::kBox;
  box.size = Eigen::Vector3d(1.0, 2.0, 0.5);
  box.X_WO.translation() = Eigen::Vector3d(10, 0, 1);
  const TriangleMesh mesh = PrimitiveMesh(box);
  ASSERT_EQ(mesh.triangles.cols(), 12);
  const Eigen::Vector3f centre(10, 0, 1);
  for (Eigen::Index t = 0; t < 12; ++t) {
    const Eigen::Vector3f a = mesh.vertices.col(mesh.triangles(0, t));
    const Eigen::Vector3f b = mesh.vertices.col(mesh.triangles(1, t));
    const Eigen::Vector3f c = mesh.vertices.col(mesh.triangles(2, t));
    EXPECT_GT((b - a).cross(c - a).dot(a - centre), 0.0f) << "triangle " << t << " faces inward";
  }
  EXPECT_EQ(mesh.vertices.rowwise().maxCoeff(), Eigen::Vector3f(11, 2, 1.5));
}

TEST(MeshTest, RevolvedShapesHaveAVertexOnLocalXAndTheirRadius) {
  Primitive cylinder;
  cylinder.shape = ShapeType::kCylinder;
  cylinder.size = Eigen::Vector3d(0.5, 1.0, 0.0);
  cylinder.X_WO.translation() = Eigen::Vector3d(3, 0, 1);
  const TriangleMesh mesh = PrimitiveMesh(cylinder, 24);
  bool vertex_on_x = false;
  for (Eigen::Index v = 0; v < mesh.vertices.cols(); ++v) {
    const Eigen::Vector3f p = mesh.vertices.col(v) - Eigen::Vector3f(3, 0, 1);
    const float radius = std::hypot(p.x(), p.y());
    EXPECT_TRUE(radius < 1e-6f || std::abs(radius - 0.5f) < 1e-6f);
    EXPECT_LE(std::abs(p.z()), 1.0f + 1e-6f);
    vertex_on_x |= std::abs(p.x() - 0.5f) < 1e-6f && std::abs(p.y()) < 1e-6f;
  }
  EXPECT_TRUE(vertex_on_x);
  // 24 side quads and 24 triangles in each cap
  EXPECT_EQ(mesh.triangles.cols(), 24 * 2 + 2 * 24);
}

TEST(MeshTest, SurfaceSamplesAreDenseEnoughAndOnTheSurface) {
  Primitive box;
  box.size = Eigen::Vector3d(0.5, 0.5, 0.5);
  const PointCloud samples = SampleSurface(PrimitiveMesh(box), 0.1);
  // every sample lies on the cube's surface (one coordinate at +-0.5)
  for (Eigen::Index i = 0; i < samples.size(); ++i) {
    EXPECT_NEAR(samples.points.col(i).cwiseAbs().maxCoeff(), 0.5f, 1e-6f);
  }
  // a 1 m^2 face at 0.1 m spacing holds at least 100 samples; 6 faces
  EXPECT_GE(samples.size(), 600);
}

}  // namespace
}  // namespace trav::common
