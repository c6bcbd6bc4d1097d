// A batch's contact sheet: its HTML cells and links, and its tiled PNG's frames and thumbnails.
#include "scenarios/experiments/contact_sheet.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "renders/image.h"
#include "tests/cli_test_util.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::Not;

// A solid RGB image.
renders::Image Solid(int width, int height, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  renders::Image image;
  image.width = width;
  image.height = height;
  for (int i = 0; i < width * height; ++i) image.rgb.insert(image.rgb.end(), {r, g, b});
  return image;
}

Eigen::Vector3i At(const renders::Image& image, int x, int y) {
  const std::uint8_t* p = image.Pixel(x, y);
  return {p[0], p[1], p[2]};
}

TEST(ContactSheetTest, OneFramedThumbnailAndOneLabelledCellPerRun) {
  const fs::path folder = test_util::FreshTestFolder("contact_sheet_test");
  // run a: finished, a map and a video; b: finished, a damaged map, no video; c: failed to
  // finish (only its record in failed/)
  fs::create_directories(folder / "runs" / "a");
  fs::create_directories(folder / "runs" / "b");
  fs::create_directories(folder / "failed");
  renders::WritePng((folder / "runs" / "a" / "map_paths.png").string(), Solid(800, 400, 0, 0, 255));
  std::ofstream(folder / "runs" / "a" / "video.mp4") << "video";
  std::ofstream(folder / "runs" / "b" / "map_paths.png") << "not a PNG";
  std::ofstream(folder / "runs" / "b" / "summary.json") << "{}";
  std::ofstream(folder / "failed" / "c.json") << "{}";
  std::vector<BatchResult> results(3);
  results[0].id = "a";
  results[0].outcome = "success";
  results[0].success = true;
  results[0].parameters = {{"speed", "1.5"}};
  results[1].id = "b";
  results[1].outcome = "collision";
  results[1].parameters = {{"note", "<b>&"}};
  results[2].id = "c";
  results[2].outcome = "crashed";

  EXPECT_THAT(WriteContactSheet(folder.string(), results),
              ElementsAre("contact_sheet.html", "contact_sheet.png"));
  const std::string html = test_util::ReadFile(folder / "contact_sheet.html");
  EXPECT_THAT(html, HasSubstr("<a href=\"runs/a/video.mp4\"><img src=\"runs/a/map_paths.png\""));
  EXPECT_THAT(html, HasSubstr("speed = 1.5"));
  EXPECT_THAT(html, HasSubstr("<a href=\"runs/b/summary.json\"><div class=\"none\">no image"));
  EXPECT_THAT(html, HasSubstr("note = &lt;b&gt;&amp;"));  // text from files is escaped
  EXPECT_THAT(html, Not(HasSubstr("<b>&")));
  EXPECT_THAT(html, HasSubstr("<a href=\"failed/c.json\">"));
  EXPECT_THAT(html, HasSubstr("class=\"run ok\""));
  EXPECT_THAT(html, HasSubstr("crashed"));

  // three cells of 200 + 2 x 4 pixels in a row
  const renders::Image sheet =
      renders::ReadPngRgb((folder / "contact_sheet.png").string(), 1'000'000);
  ASSERT_EQ(sheet.width, 3 * 208);
  ASSERT_EQ(sheet.height, 208);
  EXPECT_EQ(At(sheet, 0, 0), Eigen::Vector3i(40, 170, 70));    // a: success frame
  EXPECT_EQ(At(sheet, 208, 0), Eigen::Vector3i(210, 40, 40));  // b: failure frame
  EXPECT_EQ(At(sheet, 416 + 3, 100), Eigen::Vector3i(210, 40, 40));
  // a's 800 x 400 map shrunk to 200 x 100, centred: blue in the middle, grey above and below
  EXPECT_EQ(At(sheet, 104, 104), Eigen::Vector3i(0, 0, 255));
  EXPECT_EQ(At(sheet, 104, 20), Eigen::Vector3i(90, 90, 90));
  EXPECT_EQ(At(sheet, 208 + 104, 104), Eigen::Vector3i(90, 90, 90));  // b: no image
  // nothing partial left
  for (const auto& entry : fs::directory_iterator(folder)) {
    EXPECT_THAT(entry.path().filename().string(), Not(HasSubstr("partial")));
  }
  fs::remove_all(folder);
}

TEST(ContactSheetTest, WithoutAnyImageOnlyTheHtmlIsWritten) {
  const fs::path folder = test_util::FreshTestFolder("contact_sheet_test");
  std::vector<BatchResult> results(1);
  results[0].id = "only";
  results[0].outcome = "timeout";
  EXPECT_THAT(WriteContactSheet(folder.string(), results), ElementsAre("contact_sheet.html"));
  EXPECT_FALSE(fs::exists(folder / "contact_sheet.png"));
  fs::remove_all(folder);
}

TEST(DownscaleTest, AveragesTheCoveredPixelsAndKeepsTheAspectRatio) {
  renders::Image image = Solid(4, 2, 0, 0, 0);
  image.rgb[0] = 200;  // pixel (0, 0) red 200: the 2 x 2 block's mean is 50
  const renders::Image small = renders::Downscale(image, 2, 2);
  ASSERT_EQ(small.width, 2);
  ASSERT_EQ(small.height, 1);
  EXPECT_EQ(At(small, 0, 0), Eigen::Vector3i(50, 0, 0));
  EXPECT_EQ(At(small, 1, 0), Eigen::Vector3i(0, 0, 0));
  EXPECT_EQ(renders::Downscale(image, 8, 8).width, 4);  // within the size: unchanged
}

}  // namespace
}  // namespace trav::scenarios
