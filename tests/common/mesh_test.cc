#include "common/mesh.h"

#include <cmath>

#include <gtest/gtest.h>

namespace trav::common {
namespace {

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
