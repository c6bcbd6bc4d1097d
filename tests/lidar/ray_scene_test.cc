#include "sim/lidar/ray_scene.h"

#include <cmath>

#include <gtest/gtest.h>

#include "sim/lidar/scan_pattern.h"
#include "tests/lidar/lidar_test_util.h"

namespace trav::lidar {
namespace {

using common::ShapeType;
using testing::At;
using testing::MakePrimitive;
using testing::Plane;

Eigen::Matrix3Xf Single(const Eigen::Vector3f& direction) { return direction.normalized(); }

TEST(RaySceneTest, DownwardRaysOverAPlaneHitAtOneOverSinOfTheDepression) {
  RaySceneDescription description;
  description.meshes_W.push_back(Plane(200.0, 0.0));
  const RayScene dut(description);
  // one MID-360 frame from 1 m above the plane
  const ProceduralMid360Pattern pattern;
  Eigen::Matrix3Xf directions(3, 20000);
  for (int i = 0; i < 20000; ++i) directions.col(i) = pattern.Ray(i).direction_L;
  RayHits hits;
  dut.Cast(Eigen::Vector3f(0, 0, 1), directions, 100.0f, &hits);
  int downward = 0;
  for (int i = 0; i < 20000; ++i) {
    const float dz = directions(2, i);
    if (dz < -0.0175f) {  // below -1 deg: within 100 m
      ++downward;
      ASSERT_EQ(hits.object_id[i], 0);
      EXPECT_NEAR(hits.range_m[i], 1.0f / -dz, 2e-6f / -dz) << "ray " << i;
      EXPECT_NEAR(hits.normal_W(2, i), 1.0f, 1e-6f);
    } else if (dz >= 0.0f) {
      EXPECT_EQ(hits.object_id[i], -1);
      EXPECT_TRUE(std::isinf(hits.range_m[i]));
    }
  }
  EXPECT_GT(downward, 1000);
}

TEST(RaySceneTest, BoxAndCylinderAtKnownDistances) {
  RaySceneDescription description;
  description.primitives_W.push_back(MakePrimitive(ShapeType::kBox, {1, 1, 1}, {5, 0, 0}));
  description.primitives_W.push_back(MakePrimitive(ShapeType::kCylinder, {0.5, 1, 0}, {0, 6, 0}));
  description.primitives_W.push_back(MakePrimitive(ShapeType::kSphere, {2, 0, 0}, {0, -10, 0}));
  const RayScene dut(description);
  EXPECT_EQ(dut.num_objects(), 3);
  RayHits hits;
  Eigen::Matrix3Xf directions(3, 3);
  directions << 1, 0, 0, 0, 1, -1, 0, 0, 0;
  dut.Cast(Eigen::Vector3f::Zero(), directions, 40.0f, &hits);
  EXPECT_FLOAT_EQ(hits.range_m[0], 4.0f);
  EXPECT_EQ(hits.object_id[0], 0);
  EXPECT_TRUE(hits.normal_W.col(0).isApprox(Eigen::Vector3f(-1, 0, 0)));
  // the cylinder's polygon has a vertex where the ray meets it: exactly the radius
  EXPECT_FLOAT_EQ(hits.range_m[1], 5.5f);
  EXPECT_EQ(hits.object_id[1], 1);
  EXPECT_FLOAT_EQ(hits.range_m[2], 8.0f);
  EXPECT_EQ(hits.object_id[2], 2);
}

TEST(RaySceneTest, MovingObjectIsHitAtItsNewPose) {
  RaySceneDescription description;
  description.meshes_W.push_back(Plane(50.0, -1.0));
  description.moving_meshes_I.push_back(
      common::PrimitiveMesh(MakePrimitive(ShapeType::kBox, {0.5, 0.5, 0.5}, {0, 0, 0})));
  description.X_WI.push_back(At({3, 0, 0}));
  RayScene dut(description);
  RayHits hits;
  const Eigen::Matrix3Xf forward = Single(Eigen::Vector3f::UnitX());
  dut.Cast(Eigen::Vector3f::Zero(), forward, 40.0f, &hits);
  EXPECT_FLOAT_EQ(hits.range_m[0], 2.5f);
  EXPECT_EQ(hits.object_id[0], 1);
  dut.SetMovingPose(0, At({7, 0, 0}));
  dut.Cast(Eigen::Vector3f::Zero(), forward, 40.0f, &hits);
  EXPECT_FLOAT_EQ(hits.range_m[0], 6.5f);
  // turned 90 deg about z: the normal of the face hit still faces the sensor
  Eigen::Isometry3d turned = At({4, 0, 0});
  turned.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  dut.SetMovingPose(0, turned);
  dut.Cast(Eigen::Vector3f::Zero(), forward, 40.0f, &hits);
  EXPECT_FLOAT_EQ(hits.range_m[0], 3.5f);
  EXPECT_TRUE(hits.normal_W.col(0).isApprox(Eigen::Vector3f(-1, 0, 0), 1e-6f));
  EXPECT_THROW(dut.SetMovingPose(1, At({0, 0, 0})), std::out_of_range);
}

// Every moving object placed at once (one rebuild of the top level): each is hit at its new pose,
// the same as placing them one by one; placing them where they are changes nothing.
TEST(RaySceneTest, MovingObjectsPlacedTogetherAreHitAtTheirNewPoses) {
  RaySceneDescription description;
  description.meshes_W.push_back(Plane(50.0, -1.0));
  for (int k = 0; k < 2; ++k) {
    description.moving_meshes_I.push_back(
        common::PrimitiveMesh(MakePrimitive(ShapeType::kBox, {0.5, 0.5, 0.5}, {0, 0, 0})));
  }
  description.X_WI = {At({3, 0, 0}), At({0, 3, 0})};
  RayScene together(description), one_by_one(description);
  EXPECT_EQ(together.num_moving(), 2);
  Eigen::Matrix3Xf directions(3, 2);
  directions << 1, 0, 0, 1, 0, 0;
  const std::vector<Eigen::Isometry3d> poses = {At({7, 0, 0}), At({0, 5, 0})};
  together.SetMovingPoses(poses);
  together.SetMovingPoses(poses);
  one_by_one.SetMovingPose(0, poses[0]);
  one_by_one.SetMovingPose(1, poses[1]);
  RayHits hits, reference;
  together.Cast(Eigen::Vector3f::Zero(), directions, 40.0f, &hits);
  one_by_one.Cast(Eigen::Vector3f::Zero(), directions, 40.0f, &reference);
  EXPECT_FLOAT_EQ(hits.range_m[0], 6.5f);
  EXPECT_EQ(hits.object_id[0], 1);
  EXPECT_FLOAT_EQ(hits.range_m[1], 4.5f);
  EXPECT_EQ(hits.object_id[1], 2);
  EXPECT_EQ(hits.range_m.head(2), reference.range_m.head(2));
  EXPECT_THROW(together.SetMovingPoses({At({0, 0, 0})}), std::out_of_range);
}

TEST(RaySceneTest, RangeLimitTurnsFarHitsIntoMisses) {
  RaySceneDescription description;
  description.primitives_W.push_back(MakePrimitive(ShapeType::kBox, {1, 1, 1}, {30, 0, 0}));
  const RayScene dut(description);
  RayHits hits;
  dut.Cast(Eigen::Vector3f::Zero(), Single(Eigen::Vector3f::UnitX()), 20.0f, &hits);
  EXPECT_EQ(hits.object_id[0], -1);
  EXPECT_TRUE(std::isinf(hits.range_m[0]));
}

TEST(RaySceneTest, SpheresAreHitOnTheirExactSurfaces) {
  // tree crowns: spheres of radius 2 at y = -10 and 1 at x = 6, z = 1
  RaySceneDescription description;
  description.primitives_W.push_back(MakePrimitive(ShapeType::kSphere, {2, 0, 0}, {0, -10, 0}));
  description.primitives_W.push_back(MakePrimitive(ShapeType::kSphere, {1, 0, 0}, {6, 0, 1}));
  const RayScene dut(description);
  const std::vector<Eigen::Vector3d> centres_W = {{0, -10, 0}, {6, 0, 1}};
  const std::vector<double> radii_m = {2.0, 1.0};
  // between its vertices a tessellation with 48 segments around lies up to 0.2 % of the radius
  // inside the sphere, and farther between its rings (4 mm and more at 2 m): these rays fall there
  Eigen::Matrix3Xd directions(3, 34);
  for (int k = 0; k < 17; ++k) {
    const double angle = -0.19 + 0.0237 * k;
    directions.col(k) = Eigen::Vector3d(std::sin(angle), -std::cos(angle), 0.05).normalized();
    directions.col(17 + k) =
        Eigen::Vector3d(1.0, 0.5 * angle, 1.0 / 6.0 + 0.5 * angle).normalized();
  }
  RayHits hits;
  dut.Cast(Eigen::Vector3f::Zero(), directions.cast<float>(), 40.0f, &hits);
  for (int i = 0; i < directions.cols(); ++i) {
    SCOPED_TRACE(i);
    const int sphere = i < 17 ? 0 : 1;
    // the first root of |t d - c|^2 = r^2
    const Eigen::Vector3d& c = centres_W[static_cast<std::size_t>(sphere)];
    const double r = radii_m[static_cast<std::size_t>(sphere)];
    const double along = directions.col(i).dot(c);
    const double range_m = along - std::sqrt(along * along - (c.squaredNorm() - r * r));
    ASSERT_EQ(hits.object_id[i], sphere);
    EXPECT_NEAR(hits.range_m[i], range_m, 1e-4);
    const Eigen::Vector3d normal_W = (range_m * directions.col(i) - c) / r;
    EXPECT_TRUE(hits.normal_W.col(i).cast<double>().isApprox(normal_W, 1e-4));
  }
}

TEST(RaySceneTest, ThreadsDoNotChangeTheResults) {
  RaySceneDescription description;
  description.meshes_W.push_back(Plane(30.0, 0.0));
  description.primitives_W.push_back(MakePrimitive(ShapeType::kCylinder, {0.3, 2, 0}, {2, 1, 0}));
  const RayScene dut(description);
  const ProceduralMid360Pattern pattern;
  Eigen::Matrix3Xf directions(3, 10000);
  for (int i = 0; i < 10000; ++i) directions.col(i) = pattern.Ray(i).direction_L;
  RayHits one, two;
  dut.Cast(Eigen::Vector3f(0, 0, 0.5), directions, 40.0f, &one, 1);
  dut.Cast(Eigen::Vector3f(0, 0, 0.5), directions, 40.0f, &two, 2);
  EXPECT_TRUE((one.range_m.array() == two.range_m.array() ||
               (one.range_m.array().isInf() && two.range_m.array().isInf()))
                  .all());
  EXPECT_TRUE((one.object_id.array() == two.object_id.array()).all());
}

}  // namespace
}  // namespace trav::lidar
