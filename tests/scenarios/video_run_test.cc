// A closed loop's video end to end: `trav run` of a short navigate scenario with video, its frames
// counted and its last frame decoded (ffmpeg) and checked where the layout puts the map panel's
// colour bar and the end card.
#include <array>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/cli_test_util.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 320, kHeight = 240, kPanelWidth = 120;  // the panel: 3/8 of the width

constexpr char kNavigate[] = R"(
schema_version: 1
name: video
terrain: {type: hilly, seed: 3, size: [16, 16], resolution: 0.1}
robot: {start: [-5, 0, 0]}
goal: [5, 0]
duration: 2
mode: navigate
expect: timeout
video: {enabled: true, width: 320, height: 240, fps: 10, end_card: 1, camera: top_down}
)";

// A frame of the last 0.3 s of `video` as RGB rows (top to bottom), decoded by ffmpeg.
std::vector<std::uint8_t> FrameNearTheEnd(const fs::path& video) {
  const std::string command = "ffmpeg -loglevel error -sseof -0.3 -i '" + video.string() +
                              "' -frames:v 1 -f rawvideo -pix_fmt rgb24 -";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(kWidth) * kHeight * 3);
  if (!pipe || std::fread(rgb.data(), 1, rgb.size(), pipe.get()) != rgb.size()) rgb.clear();
  return rgb;
}

TEST(VideoRunTest, AClosedLoopsVideoHasItsFramesItsPanelAndItsEndCard) {
  const fs::path root = test_util::FreshTestFolder("video_run_test");
  const fs::path scenario = root / "video.yaml";
  std::ofstream(scenario) << kNavigate;
  const test_util::CommandResult result =
      test_util::RunTrav("run " + scenario.string() + " --out " + (root / "run").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json summary =
      nlohmann::json::parse(test_util::ReadFile(root / "run" / "summary.json"));
  // a frame every 0.1 s of the 2 s, the last state with the outcome, then 1 s of end card
  EXPECT_EQ(summary["video_frames"].get<int>(), 20 + 1 + 10);

  const std::vector<std::uint8_t> rgb = FrameNearTheEnd(root / "run" / "video.mp4");
  ASSERT_EQ(rgb.size(), static_cast<std::size_t>(kWidth) * kHeight * 3);
  auto pixel = [&](int x, int y) {
    const std::uint8_t* p = rgb.data() + 3 * (static_cast<std::size_t>(y) * kWidth + x);
    return std::array<int, 3>{p[0], p[1], p[2]};
  };
  // the panel's colour bar under its square map: one row where its left end is green and its
  // right end red (H.264 blurs edges: a few pixels in from each end)
  const int view_width = kWidth - kPanelWidth;
  bool bar_found = false;
  for (int y = kPanelWidth; y < kHeight && !bar_found; ++y) {
    const auto left = pixel(view_width + 8, y), right = pixel(kWidth - 8, y);
    bar_found = left[1] > left[0] + 60 && left[1] > left[2] + 60 && right[0] > right[1] + 80 &&
                right[0] > right[2] + 80;
  }
  EXPECT_TRUE(bar_found);
  // the end card: dark in the middle of the view, where its text is not
  int dark = 0;
  for (int y = kHeight / 2 - 10; y < kHeight / 2 + 10; ++y) {
    for (int x = 20; x < 40; ++x) {
      const auto p = pixel(x, y);
      dark += p[0] + p[1] + p[2] < 180 ? 1 : 0;
    }
  }
  EXPECT_GT(dark, 300);
  fs::remove_all(root);
}

}  // namespace
}  // namespace trav::scenarios
