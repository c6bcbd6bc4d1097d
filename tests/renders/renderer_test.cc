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
using testing::GrayStandardDeviation;
using testing::IsRobotRed;
using testing::WorldWithMoundAndMover;

GlBackend BackendUnderTest() {
  const char* name = std::getenv("TRAV_TEST_GL_BACKEND");
  return name != nullptr && std::strcmp(name, "egl") == 0 ? GlBackend::kEgl : GlBackend::kOsmesa;
}

// Where the test world's mound and mover stand (in the top-down view's corners) [m].
const Eigen::Vector2d kMound_W(2.4, 1.7);
const Eigen::Vector2d kMover_W(-2.5, -1.6);

// The top-down test view: 6 m above the origin, MuJoCo's default 45 deg field of view, on the
// 320 x 240 frame: 120 pixels are 6 tan(22.5 deg) metres.
constexpr double kPixelsPerMetre = 120.0 / (6.0 * 0.41421356);
Eigen::Vector2d PixelOf(const Eigen::Vector2d& p_W) {
  return {160.0 + kPixelsPerMetre * p_W.x(), 120.0 - kPixelsPerMetre * p_W.y()};
}

// One simulation and renderer for the whole suite: MuJoCo 2.2's GL context is per process.
class RendererTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    simulation_ = WorldWithMoundAndMover(Eigen::Vector2d(1.5, 0.0), kMound_W, kMover_W).release();
    // the camera's view is the left 320 x 240 pixels; a panel of 80 pixels is right of it
    RenderConfig config;
    config.width = 400;
    config.height = 240;
    config.panel_width = 80;
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
  ASSERT_EQ(image.width, 400);
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
  points.size_px = 12.0f;
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
  // the yellow dot at y = +1.5: above the centre
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

TEST_F(RendererTest, PointsAreDrawnAtTheProjectionsOfTheirPositionsAndHiddenBehindSolids) {
  // three small dots on the ground at known places, one more inside the robot's body
  const std::vector<Eigen::Vector3f> hits_W = {
      {-1.0f, 1.0f, 0.0f}, {0.5f, -1.5f, 0.0f}, {-2.0f, -0.5f, 0.0f}, {1.5f, 0.0f, 0.05f}};
  ColoredPoints points;
  points.points_W.resize(3, 4);
  for (int i = 0; i < 4; ++i) points.points_W.col(i) = hits_W[static_cast<std::size_t>(i)];
  points.rgba = Eigen::Vector4f(1.0f, 0.0f, 1.0f, 1.0f);
  points.size_px = 3.0f;
  Overlay overlay;
  overlay.points.push_back(points);
  Image image;
  renderer_->Render(*simulation_, TopDownView(Eigen::Vector3d(0, 0, 0), 6.0), overlay, &image);
  auto magenta = [](int r, int g, int b) { return r > 180 && g < 90 && b > 180; };
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector2d expected =
        PixelOf(hits_W[static_cast<std::size_t>(i)].head<2>().cast<double>());
    int found = 0;
    for (int dy = -3; dy <= 3; ++dy) {
      for (int dx = -3; dx <= 3; ++dx) {
        const std::uint8_t* p =
            image.Pixel(static_cast<int>(expected.x()) + dx, static_cast<int>(expected.y()) + dy);
        found += magenta(p[0], p[1], p[2]) ? 1 : 0;
      }
    }
    EXPECT_GT(found, 0) << "point " << i << " not drawn near pixel " << expected.transpose();
  }
  // the dot inside the robot's body is hidden by it: no magenta near the robot
  const Eigen::Vector2d robot = PixelOf(Eigen::Vector2d(1.5, 0.0));
  int inside = 0;
  for (int dy = -8; dy <= 8; ++dy) {
    for (int dx = -8; dx <= 8; ++dx) {
      const std::uint8_t* p =
          image.Pixel(static_cast<int>(robot.x()) + dx, static_cast<int>(robot.y()) + dy);
      inside += magenta(p[0], p[1], p[2]) ? 1 : 0;
    }
  }
  EXPECT_EQ(inside, 0);
}

TEST_F(RendererTest, TheGroundIsPaintedGrassAndItsSteepMoundSoilOrRock) {
  Image image;
  renderer_->Render(*simulation_, TopDownView(Eigen::Vector3d(0, 0, 0), 6.0), {}, &image);
  auto grass = [](int r, int g, int b) { return g > r + 20 && g > b + 40; };
  // the mound's flanks (30 to 50 deg) are brown or grey: neither green nor the robot's red
  auto bare = [](int r, int g, int b) { return std::abs(r - g) < 30 && g >= b && r > 40; };
  const Eigen::Vector2d flat = PixelOf(Eigen::Vector2d(-1.0, 1.5));
  const std::uint8_t* p = image.Pixel(static_cast<int>(flat.x()), static_cast<int>(flat.y()));
  EXPECT_TRUE(grass(p[0], p[1], p[2])) << int(p[0]) << " " << int(p[1]) << " " << int(p[2]);
  // within 1 m of the mound (the robot's grey top is further away)
  const Eigen::Vector2d expected = PixelOf(kMound_W);
  const auto [mound, count] = Centroid(image, [&](int r, int g, int b) { return bare(r, g, b); });
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int near = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* q = image.Pixel(x, y);
      if ((Eigen::Vector2d(x, y) - expected).norm() < kPixelsPerMetre && bare(q[0], q[1], q[2])) {
        sum += Eigen::Vector2d(x, y);
        ++near;
      }
    }
  }
  ASSERT_GT(near, 30);
  // the mound's middle, where its flanks are steepest, 0.25 m up: 4 % further out in the view
  const Eigen::Vector2d centre = sum / near;
  EXPECT_NEAR(centre.x(), 160 + 1.04 * (expected.x() - 160), 8);
  EXPECT_NEAR(centre.y(), 120 + 1.04 * (expected.y() - 120), 8);
  EXPECT_GT(count, near);  // and the robot's grey, which is not ground
}

TEST_F(RendererTest, HiddenMoversAreDrawnAsWalkersWhoseLegsSwing) {
  auto violet = [](int r, int g, int b) { return r > 80 && g < 90 && b > 120; };
  // straight above the mover: the view's centre (160, 120) is the mover
  const CameraView above = TopDownView(Eigen::Vector3d(kMover_W.x(), kMover_W.y(), 0), 6.0);
  const Eigen::Vector2d mover(160, 120);
  Image image;
  renderer_->Render(*simulation_, above, {}, &image);
  const auto [capsule, capsule_count] = Centroid(image, violet);
  ASSERT_GT(capsule_count, 50);  // the mover's own capsule
  EXPECT_NEAR(capsule.x(), mover.x(), 3);
  EXPECT_NEAR(capsule.y(), mover.y(), 3);

  // hidden, and a walker facing +x drawn there instead with a different colour
  Overlay overlay;
  overlay.hidden_movers = {0};
  Walker walker;
  walker.X_WO = Eigen::Translation3d(simulation_->MoverPose(0).translation()) *
                Eigen::Isometry3d::Identity();  // facing +x
  walker.rgba = Eigen::Vector4f(0.1f, 0.8f, 0.9f, 1.0f);
  // dark blue-grey trousers; not the shaded underside of the cyan arms
  auto trousers = [](int r, int g, int b) { return r < 70 && b > r + 5 && g < 2 * r + 10; };
  auto shirt = [](int r, int g, int b) { return r < 90 && g > 150 && b > 160; };
  double left_leg_x[2];
  for (int k = 0; k < 2; ++k) {
    walker.gait_phase_rad = k == 0 ? 0.5 * M_PI : 1.5 * M_PI;
    overlay.walkers.assign(1, walker);
    renderer_->Render(*simulation_, above, overlay, &image);
    EXPECT_EQ(Centroid(image, violet).second, 0);
    const auto [body, body_count] = Centroid(image, shirt);
    ASSERT_GT(body_count, 30);
    EXPECT_NEAR(body.x(), mover.x(), 6);
    // the left leg (+y: above the body's centre row in the image) reaches forward (+x) at pi/2
    // and back at 3 pi/2
    double sum = 0.0;
    int n = 0;
    for (int y = static_cast<int>(mover.y()) - 15; y < static_cast<int>(mover.y()); ++y) {
      for (int x = static_cast<int>(mover.x()) - 30; x <= static_cast<int>(mover.x()) + 30; ++x) {
        const std::uint8_t* q = image.Pixel(x, y);
        if (trousers(q[0], q[1], q[2])) {
          sum += x;
          ++n;
        }
      }
    }
    ASSERT_GT(n, 5) << "no leg visible at phase " << walker.gait_phase_rad;
    left_leg_x[k] = sum / n;
  }
  EXPECT_GT(left_leg_x[0], mover.x() + 3);
  EXPECT_LT(left_leg_x[1], mover.x() - 3);
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

TEST_F(RendererTest, AHazardousCellOfADrapedMapIsRedWhereItLies) {
  // a 2 x 2 m map round (-1, -1), all free but one lethal 0.4 m square centred at (-0.6, -1.4)
  GroundGrid grid;
  grid.geometry =
      common::GridGeometry::Centered(Eigen::Vector2d(-1.0, -1.0), Eigen::Vector2d(2.0, 2.0), 0.1);
  grid.values = Eigen::MatrixXf::Zero(grid.geometry.num_x, grid.geometry.num_y);
  grid.heights_m = Eigen::MatrixXf::Zero(grid.geometry.num_x, grid.geometry.num_y);
  Eigen::Vector2d hazard_sum = Eigen::Vector2d::Zero();
  int hazard_cells = 0;
  for (int iy = 0; iy < grid.geometry.num_y; ++iy) {
    for (int ix = 0; ix < grid.geometry.num_x; ++ix) {
      const Eigen::Vector2d c = grid.geometry.CellCenter(ix, iy);
      if ((c - Eigen::Vector2d(-0.6, -1.4)).cwiseAbs().maxCoeff() < 0.2) {
        grid.values(ix, iy) = 1.0f;
        hazard_sum += c;
        ++hazard_cells;
      }
    }
  }
  ASSERT_GT(hazard_cells, 0);
  grid.alpha = 0.8f;
  Overlay overlay;
  overlay.grids.push_back(grid);
  Image image;
  renderer_->Render(*simulation_, TopDownView(Eigen::Vector3d(0, 0, 0), 6.0), overlay, &image);
  // red pixels left of the view's middle (the robot's red paint is at x = 1.5 m, right of it)
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int count = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < 160; ++x) {
      const std::uint8_t* p = image.Pixel(x, y);
      if (p[0] > p[1] + 80 && p[0] > p[2] + 80 && p[1] < 120) {
        sum += Eigen::Vector2d(x, y);
        ++count;
      }
    }
  }
  ASSERT_GT(count, 20);
  const Eigen::Vector2d red = sum / count;
  // the hazard's cells' centres, where their quads' corners average the red with the green
  // around it: the red centroid lies over them
  const Eigen::Vector2d expected = PixelOf(hazard_sum / hazard_cells);
  EXPECT_NEAR(red.x(), expected.x(), 4);
  EXPECT_NEAR(red.y(), expected.y(), 4);
}

TEST_F(RendererTest, CartsHaveABasketAndAHandleBehind) {
  Cart cart;
  cart.X_WO.translation() = Eigen::Vector3d(-1.0, 1.5, 0.5);  // facing +x
  cart.half_extents_m = Eigen::Vector3d(0.5, 0.35, 0.5);
  cart.rgba = Eigen::Vector4f(0.9f, 0.9f, 0.1f, 1.0f);
  Overlay overlay;
  overlay.carts.push_back(cart);
  Image image;
  renderer_->Render(*simulation_, TopDownView(Eigen::Vector3d(-1.0, 1.5, 0), 3.0), overlay, &image);
  // from 3 m above its centre: the basket's yellow in the middle, the handle's grey bar behind it
  // (left of the basket in the image, +x to the right)
  const auto [basket, basket_count] =
      Centroid(image, [](int r, int g, int b) { return r > 180 && g > 180 && b < 90; });
  ASSERT_GT(basket_count, 500);
  EXPECT_NEAR(basket.x(), 160, 4);
  EXPECT_NEAR(basket.y(), 120, 4);
  const auto [handle, handle_count] = Centroid(image, [](int r, int g, int b) {
    return std::abs(r - g) < 12 && std::abs(g - b) < 15 && r > 120;
  });
  ASSERT_GT(handle_count, 10);
  EXPECT_LT(handle.x(), basket.x() - 40);
}

TEST_F(RendererTest, ChaseCameraLooksAtTheRobotFromBehind) {
  ChaseCamera camera;
  Image image;
  renderer_->Render(*simulation_, camera.Update(simulation_->State().X_WB, 0.0), {}, &image);
  const auto [centroid, count] = Centroid(image, IsRobotRed);
  ASSERT_GT(count, 50);
  EXPECT_NEAR(centroid.x(), 160, 20);
}

TEST_F(RendererTest, ThePanelIsDrawnRightOfTheViewWithItsTexts) {
  Overlay overlay;
  overlay.panel.image.width = 80;
  overlay.panel.image.height = 240;
  overlay.panel.image.rgb.assign(80 * 240 * 3, 0);
  for (std::size_t i = 2; i < overlay.panel.image.rgb.size(); i += 3)
    overlay.panel.image.rgb[i] = 200;
  overlay.panel.texts.push_back({"MAP", Eigen::Vector2i(4, 100), Eigen::Vector3f(1, 1, 0)});
  Image image;
  renderer_->Render(*simulation_, TopDownView(Eigen::Vector3d(0, 0, 0), 6.0), overlay, &image);
  int blue = 0, yellow_rows_low = 240, yellow_rows_high = 0, yellow = 0;
  for (int y = 0; y < 240; ++y) {
    for (int x = 320; x < 400; ++x) {
      const std::uint8_t* p = image.Pixel(x, y);
      blue += (p[0] == 0 && p[1] == 0 && p[2] == 200) ? 1 : 0;
      if (p[0] > 200 && p[1] > 200 && p[2] < 100) {
        ++yellow;
        yellow_rows_low = std::min(yellow_rows_low, y);
        yellow_rows_high = std::max(yellow_rows_high, y);
      }
    }
  }
  EXPECT_GT(blue, 80 * 240 * 9 / 10);  // the panel's own pixels, exactly, but for the text
  ASSERT_GT(yellow, 10);
  // the text's glyphs start at its top-left corner, row 100, and are one line high
  EXPECT_GE(yellow_rows_low, 98);
  EXPECT_LE(yellow_rows_high, 100 + renderer_->text_height_px());
  // the camera's view is not covered: the robot is still where TopDownFrame... expects it
  EXPECT_GT(Centroid(image, IsRobotRed).second, 50);
  // a panel of the wrong size is refused
  overlay.panel.image.width = 60;
  EXPECT_THROW(
      renderer_->Render(*simulation_, TopDownView(Eigen::Vector3d(0, 0, 0), 6.0), overlay, &image),
      std::invalid_argument);
}

TEST_F(RendererTest, AnEndCardDarkensTheMiddleOfTheViewAndCarriesItsText) {
  Overlay overlay;
  overlay.texts.push_back({"success\ntime 12.0 s", TextCorner::kCenter});
  Image image;
  renderer_->Render(*simulation_, TopDownView(Eigen::Vector3d(0, 0, 0), 6.0), overlay, &image);
  const auto [white, white_count] =
      Centroid(image, [](int r, int g, int b) { return r > 240 && g > 240 && b > 240; });
  ASSERT_GT(white_count, 30);
  EXPECT_NEAR(white.x(), 160, 40);
  EXPECT_NEAR(white.y(), 120, 30);
  // the card is dark where the grass was: at the view's centre, left of the text
  const std::uint8_t* p =
      image.Pixel(160 - static_cast<int>(renderer_->TextWidthPx("time 12.0 s")) / 2 - 8, 120);
  EXPECT_LT(p[0] + p[1] + p[2], 150);
  // the corners are still grass
  const std::uint8_t* corner = image.Pixel(5, 5);
  EXPECT_GT(corner[1], corner[0] + 20);
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
