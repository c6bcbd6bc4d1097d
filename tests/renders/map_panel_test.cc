// The map panel and the ground texture, drawn on the CPU: pixels checked where geometry puts them.
#include "renders/map_panel.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "renders/ground_texture.h"

namespace trav::renders {
namespace {

// The colour of a pixel.
Eigen::Vector3i At(const Image& image, int x, int y) {
  const std::uint8_t* p = image.Pixel(x, y);
  return {p[0], p[1], p[2]};
}

// A 10 x 10 m map at 0.5 m, all free, one lethal cell (14, 4), the left column unknown.
common::GridLayers TestMap(Eigen::MatrixXf* layer) {
  common::GridLayers map(
      common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(10, 10), 0.5), {});
  *layer = Eigen::MatrixXf::Zero(map.geometry().num_x, map.geometry().num_y);
  (*layer)(14, 4) = 1.0f;
  layer->row(0).setConstant(std::numeric_limits<float>::quiet_NaN());
  return map;
}

TEST(MapPanelTest, CellsBoxesAndDiscsAreWhereTheirCoordinatesPutThem) {
  Eigen::MatrixXf layer;
  const common::GridLayers map = TestMap(&layer);
  PanelOverlay overlay;
  // the robot facing +y at (-2, 2), 0.6 x 0.4 m
  overlay.boxes.push_back(
      {Eigen::Vector2d(-2, 2), 0.5 * M_PI, Eigen::Vector2d(0.3, 0.2), Eigen::Vector3i(10, 20, 30)});
  overlay.discs.push_back({Eigen::Vector2d(3, 3), 0.5, Eigen::Vector3i(230, 0, 230), true});
  // 200 pixels for 10 m: 20 pixels a metre, pixel (100, 100) at the origin, +y up
  const Image image = DrawMapPanel(map, layer, Eigen::Vector2d::Zero(), 10.0, 200, overlay);
  ASSERT_EQ(image.width, 200);
  auto pixel = [](double x_m, double y_m) {
    return Eigen::Vector2i(static_cast<int>(100 + 20 * x_m), static_cast<int>(100 - 20 * y_m));
  };
  const Eigen::Vector2d lethal_W = map.geometry().CellCenter(14, 4);
  const Eigen::Vector2i lethal = pixel(lethal_W.x(), lethal_W.y());
  EXPECT_EQ(At(image, lethal.x(), lethal.y()),
            (255.0f * TraversabilityColor(1.0f, 0.0f, 1.0f)).cast<int>());
  const Eigen::Vector2i free = pixel(lethal_W.x() - 1.0, lethal_W.y());
  EXPECT_EQ(At(image, free.x(), free.y()),
            (255.0f * TraversabilityColor(0.0f, 0.0f, 1.0f)).cast<int>());
  EXPECT_EQ(At(image, 2, 50), Eigen::Vector3i(128, 128, 128));  // x < -4.5: unknown
  // the box: 0.4 m wide along x, 0.6 m long along y; its inside its colour (but its outline and
  // the tick to its front, 1.5 and 2 pixels wide, white), outside it not
  const Eigen::Vector2i inside = pixel(-2.1, 1.9);
  EXPECT_EQ(At(image, inside.x(), inside.y()), Eigen::Vector3i(10, 20, 30));
  const Eigen::Vector2i beside = pixel(-2.3, 2.0);  // 0.3 m along x: beyond its half width
  EXPECT_NE(At(image, beside.x(), beside.y()), Eigen::Vector3i(10, 20, 30));
  const Eigen::Vector2i ahead = pixel(-2.1, 2.15);  // 0.15 m along y: inside its half length
  EXPECT_EQ(At(image, pixel(-2.0, 2.15).x(), ahead.y()), Eigen::Vector3i(255, 255, 255));
  EXPECT_EQ(At(image, ahead.x(), ahead.y()), Eigen::Vector3i(10, 20, 30));
  const Eigen::Vector2i disc = pixel(3.0, 3.0);
  EXPECT_EQ(At(image, disc.x(), disc.y()), Eigen::Vector3i(230, 0, 230));
}

TEST(MapPanelTest, ScaleBarsAreRoundLengths) {
  EXPECT_DOUBLE_EQ(ScaleBarLength(0.7), 0.5);
  EXPECT_DOUBLE_EQ(ScaleBarLength(3.4), 2.0);
  EXPECT_DOUBLE_EQ(ScaleBarLength(7.9), 5.0);
  EXPECT_DOUBLE_EQ(ScaleBarLength(10.0), 10.0);
  EXPECT_DOUBLE_EQ(ScaleBarLength(19.9), 10.0);
}

TEST(MapPanelTest, TheLayoutCarriesAColourBarAScaleBarAndTheLegend) {
  Image map;
  map.width = map.height = 200;
  map.rgb.assign(200 * 200 * 3, 77);
  const std::vector<LegendEntry> legend = {
      {LegendEntry::Symbol::kLine, Eigen::Vector3i(255, 255, 255), "plan"},
      {LegendEntry::Symbol::kDisc, Eigen::Vector3i(230, 0, 230), "goal"}};
  constexpr int kLine = 16;
  auto width = [](const std::string& text) { return 8 * static_cast<int>(text.size()); };
  const Panel panel = LayoutMapPanel(map, 20.0, 400, legend, "t 3.0 s", kLine, width);
  ASSERT_EQ(panel.image.width, 200);
  ASSERT_EQ(panel.image.height, 400);
  EXPECT_EQ(At(panel.image, 100, 100), Eigen::Vector3i(77, 77, 77));  // the map, unchanged
  // the colour bar: one line below the title under the map, green at its left end, red at its
  // right, yellow in the middle
  const int margin = 5, bar_row = 200 + margin / 2 + kLine + 2;
  EXPECT_EQ(At(panel.image, margin, bar_row),
            (255.0f * TraversabilityColor(0.0f, 0.0f, 1.0f)).cast<int>());
  EXPECT_EQ(At(panel.image, 200 - margin - 1, bar_row),
            (255.0f * TraversabilityColor(1.0f, 0.0f, 1.0f)).cast<int>());
  const Eigen::Vector3i middle = At(panel.image, 100, bar_row);
  EXPECT_GT(middle.x(), 200);
  EXPECT_GT(middle.y(), 190);
  EXPECT_LT(middle.z(), 60);
  // the texts: the title, the ticks, "unknown", the scale bar's length (a third of 200 pixels
  // for 20 m is 6.7 m: 5 m, 50 pixels), the legend's labels right of their symbols, the info
  auto find = [&](const std::string& text) -> const PanelText* {
    for (const PanelText& t : panel.texts) {
      if (t.text == text) return &t;
    }
    return nullptr;
  };
  for (const char* expected : {"traversability cost", "0 free", "0.5", "1 lethal", "unknown", "5 m",
                               "plan", "goal", "t 3.0 s"}) {
    EXPECT_NE(find(expected), nullptr) << expected;
  }
  ASSERT_NE(find("1 lethal"), nullptr);
  EXPECT_EQ(find("1 lethal")->top_left_px.x(), 200 - margin - width("1 lethal"));
  ASSERT_NE(find("5 m"), nullptr);
  const int scale_row = find("5 m")->top_left_px.y() + kLine / 2;
  int white = 0;
  for (int x = 0; x < 200; ++x)
    white += At(panel.image, x, scale_row) == Eigen::Vector3i(255, 255, 255);
  EXPECT_EQ(white, 50);
  ASSERT_NE(find("goal"), nullptr);
  const PanelText& goal = *find("goal");
  EXPECT_GT(goal.top_left_px.x(), 100);  // the second column
  EXPECT_EQ(At(panel.image, goal.top_left_px.x() - margin / 2 - kLine / 2,
               goal.top_left_px.y() + kLine / 2),
            Eigen::Vector3i(230, 0, 230));
  EXPECT_THROW(LayoutMapPanel(map, 20.0, 100, legend, "", kLine, width), std::invalid_argument);
}

TEST(GroundTextureTest, FlatGroundIsGrassAndASteepBandIsSoilOrRockOnItsRows) {
  // 10 x 10 m, samples every metre; a 45 deg ramp between y = 2 and y = 3, flat elsewhere
  Eigen::MatrixXf height_m = Eigen::MatrixXf::Zero(11, 11);
  for (int iy = 3; iy < 11; ++iy) height_m.col(iy).setConstant(1.0f);
  const std::vector<std::uint8_t> rgb =
      GroundTexture(height_m, Eigen::Vector2d(10, 10), GroundMaterial::kGrass, 100);
  ASSERT_EQ(rgb.size(), 100u * 100u * 3u);
  auto texel = [&](int row, int column) {
    const std::uint8_t* p = rgb.data() + 3 * (row * 100 + column);
    return Eigen::Vector3i(p[0], p[1], p[2]);
  };
  // row r covers y in [r / 10, (r + 1) / 10) m: the ramp is rows 20 to 29
  for (const int row : {5, 15, 45, 80}) {
    const Eigen::Vector3i c = texel(row, 50);
    EXPECT_GT(c.y(), c.x()) << "row " << row;  // green
    EXPECT_GT(c.y(), c.z() + 30) << "row " << row;
  }
  const Eigen::Vector3i steep = texel(25, 50);
  EXPECT_LT(std::abs(steep.x() - steep.y()), 30);  // grey or brown, not green
  EXPECT_GE(steep.x(), steep.z());
  // the same ground always looks the same
  EXPECT_EQ(rgb, GroundTexture(height_m, Eigen::Vector2d(10, 10), GroundMaterial::kGrass, 100));
}

TEST(GroundTextureTest, AFloorHasJointsEveryMetre) {
  const Eigen::MatrixXf height_m = Eigen::MatrixXf::Zero(2, 2);
  const std::vector<std::uint8_t> rgb =
      GroundTexture(height_m, Eigen::Vector2d(4, 4), GroundMaterial::kFloor, 400);
  // texels 1 cm wide: the joint at x = 1 m is column 100 (its centre 1.005 m), a tile's middle
  // column 150
  const std::uint8_t* joint = rgb.data() + 3 * (250 * 400 + 100);
  const std::uint8_t* tile = rgb.data() + 3 * (250 * 400 + 150);
  EXPECT_LT(joint[0] + 60, tile[0]);
}

}  // namespace
}  // namespace trav::renders
