// Rendered frames checked for content. The GL backend comes from TRAV_TEST_GL_BACKEND
// (osmesa or egl): ctest runs this program once per backend, as one process uses one backend.
#include "renders/renderer.h"

#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>

#include <gtest/gtest.h>

#include "tests/renders/render_test_util.h"

namespace trav::renders {
namespace {

using testing::Centroid;
using testing::FlatWorldWithRobotAt;
using testing::GrayStandardDeviation;
using testing::IsRobotRed;

GlBackend BackendUnderTest() {
  const char* name = std::getenv("TRAV_TEST_GL_BACKEND");
  return name != nullptr && std::strcmp(name, "egl") == 0 ? GlBackend::kEgl : GlBackend::kOsmesa;
}

// One simulation and renderer for the whole suite: MuJoCo 2.2's GL context is per process.
class RendererTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    simulation_ = FlatWorldWithRobotAt(Eigen::Vector2d(1.5, 0.0)).release();
    RenderConfig config;
    config.width = 320;
    config.height = 240;
    config.backend = BackendUnderTest();
    renderer_ = new Renderer(simulation_, config);
  }
  static void TearDownTestSuite() {
    delete renderer_;
    delete simulation_;
  }
  static sim::Simulation* simulation_;
  static Renderer* renderer_;
};
sim::Simulation* RendererTest::simulation_ = nullptr;
Renderer* RendererTest::renderer_ = nullptr;

TEST_F(RendererTest, TopDownFrameShowsTheRobotWhereTheCameraShouldSeeIt) {
  Image image;
  renderer_->Render(*simulation_, TopDownView(Eigen::Vector3d(0, 0, 0), 6.0), {}, &image);
  ASSERT_EQ(image.width, 320);
  ASSERT_EQ(image.height, 240);
  EXPECT_GT(GrayStandardDeviation(image), 5.0);
  // the robot is 1.5 m along +x from the point below the camera: right of the centre (the image's
  // right is +x, its top +y), on the middle row
  const auto [centroid, count] = Centroid(image, IsRobotRed);
  ASSERT_GT(count, 50);
  EXPECT_GT(centroid.x(), 160 + 30);
  EXPECT_NEAR(centroid.y(), 120, 12);
}

TEST_F(RendererTest, OverlaysAreDrawnInTheScene) {
  Overlay overlay;
  Polyline line;
  line.points_W = {Eigen::Vector3d(-2, -2, 0.05), Eigen::Vector3d(-2, 2, 0.05)};
  line.rgba = Eigen::Vector4f(0.1f, 0.2f, 1.0f, 1.0f);
  line.width_m = 0.15;
  overlay.polylines.push_back(line);
  ColoredPoints points;
  points.points_W = Eigen::Matrix3Xf(3, 1);
  points.points_W.col(0) = Eigen::Vector3f(0, 1.5, 0.3);
  points.rgba = Eigen::Vector4f(1.0f, 1.0f, 0.0f, 1.0f);
  points.radius_m = 0.2;
  overlay.points.push_back(points);
  overlay.texts.push_back({"trav", TextCorner::kTopLeft});

  Image image;
  renderer_->Render(*simulation_, TopDownView(Eigen::Vector3d(0, 0, 0), 6.0), overlay, &image);
  // the blue line runs along y at x = -2: left of the centre, spanning rows above and below it
  const auto [blue, blue_count] =
      Centroid(image, [](int r, int g, int b) { return b > 150 && r < 90 && g < 120; });
  ASSERT_GT(blue_count, 100);
  EXPECT_LT(blue.x(), 160 - 50);
  EXPECT_NEAR(blue.y(), 120, 15);
  // the yellow sphere at y = +1.5: above the centre
  const auto [yellow, yellow_count] =
      Centroid(image, [](int r, int g, int b) { return r > 150 && g > 150 && b < 80; });
  ASSERT_GT(yellow_count, 20);
  EXPECT_LT(yellow.y(), 120 - 30);
  EXPECT_NEAR(yellow.x(), 160, 15);
  // the text is white in the top-left corner
  const auto [text, text_count] =
      Centroid(image, [](int r, int g, int b) { return r > 240 && g > 240 && b > 240; });
  ASSERT_GT(text_count, 10);
  EXPECT_LT(text.x(), 80);
  EXPECT_LT(text.y(), 40);
}

TEST_F(RendererTest, GroundGridsShowTheirKnownCellsOnly) {
  GroundGrid grid;
  grid.geometry =
      common::GridGeometry::Centered(Eigen::Vector2d(-1.5, 1.0), Eigen::Vector2d(1.0, 1.0), 0.1);
  grid.values = Eigen::MatrixXf::Zero(grid.geometry.num_x, grid.geometry.num_y);  // easy: green
  grid.heights_m = Eigen::MatrixXf::Zero(grid.geometry.num_x, grid.geometry.num_y);
  grid.values.rightCols(5).setConstant(
      std::numeric_limits<float>::quiet_NaN());  // unknown: not drawn
  grid.alpha = 1.0f;
  Overlay overlay;
  overlay.grids.push_back(grid);
  Image image;
  renderer_->Render(*simulation_, TopDownView(Eigen::Vector3d(0, 0, 0), 6.0), overlay, &image);
  const auto [green, count] =
      Centroid(image, [](int r, int g, int b) { return g > r + 60 && g > b + 60; });
  // the known half of the patch: x in [-2, -1], y in [0.5, 0.9]: left of and above the centre
  ASSERT_GT(count, 100);
  EXPECT_LT(green.x(), 160 - 40);
  EXPECT_LT(green.y(), 120 - 20);
  EXPECT_GT(green.y(), 120 - 60);
}

TEST_F(RendererTest, ChaseCameraLooksAtTheRobotFromBehind) {
  ChaseCamera camera;
  Image image;
  renderer_->Render(*simulation_, camera.Update(simulation_->State().X_WB, 0.0), {}, &image);
  const auto [centroid, count] = Centroid(image, IsRobotRed);
  ASSERT_GT(count, 50);
  EXPECT_NEAR(centroid.x(), 160, 20);
}

TEST(TraversabilityColorTest, RunsFromGreenThroughYellowToRed) {
  const Eigen::Vector3f low = TraversabilityColor(0.0f, 0.0f, 1.0f);
  const Eigen::Vector3f mid = TraversabilityColor(0.5f, 0.0f, 1.0f);
  const Eigen::Vector3f high = TraversabilityColor(2.0f, 0.0f, 1.0f);
  EXPECT_GT(low.y(), low.x());
  EXPECT_GT(mid.x(), 0.9f);
  EXPECT_GT(mid.y(), 0.8f);
  EXPECT_GT(high.x(), 0.8f);
  EXPECT_LT(high.y(), 0.15f);
}

}  // namespace
}  // namespace trav::renders
