// Every scenario file the repository ships loads as a valid scenario (batch files, which list
// scenarios, are left to batch_files_test), and the imported BARN worlds keep BARN's layout.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/yaml_reader.h"
#include "scenarios/run/scenario.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;

// The scenario files under scenarios/<folder>, sorted; batch files (a top-level `scenarios:` list)
// are left out.
std::vector<fs::path> ScenarioFiles(const std::string& folder) {
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry :
       fs::directory_iterator(fs::path(TRAV_SOURCE_DIR) / "scenarios" / folder)) {
    if (entry.path().extension() != ".yaml") continue;
    if (common::YamlDocument::Load(entry.path().string()).Find("scenarios")) continue;
    files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(ShippedScenariosTest, EveryScenarioFileLoads) {
  int loaded = 0;
  for (const char* folder :
       {"suite", "failing", "hard", "track", "stress", "barn", "terrain_files"}) {
    for (const fs::path& file : ScenarioFiles(folder)) {
      EXPECT_NO_THROW(LoadScenario(common::YamlDocument::Load(file.string()))) << file;
      ++loaded;
    }
  }
  EXPECT_GE(loaded, 300 + 9 + 3 + 4 + 1);
}

TEST(ShippedScenariosTest, TheBarnWorldsKeepBarnsLayoutScaledToTheScoutMini) {
  const std::vector<fs::path> files = ScenarioFiles("barn");
  ASSERT_EQ(files.size(), 300u);
  constexpr double kScale = 0.570 / 0.430;  // Scout Mini width / Jackal width
  for (const fs::path& file : files) {
    const Scenario s = LoadScenario(common::YamlDocument::Load(file.string()));
    // BARN's start (-2.25, 3) facing +y and goal 10 m ahead, about (-2.25, 6.5) as the origin
    EXPECT_NEAR(s.start_W.position.x(), 0.0, 1e-4) << file;
    EXPECT_NEAR(s.start_W.position.y(), kScale * (3.0 - 6.5), 1e-4) << file;
    EXPECT_NEAR(s.start_W.yaw, 0.5 * M_PI, 1e-4) << file;
    EXPECT_NEAR(s.goal_W.y() - s.start_W.position.y(), 10.0 * kScale, 1e-3) << file;
    EXPECT_EQ(s.navigation.goal_radius_m, 1.0);
    EXPECT_EQ(s.duration_s, 100.0);
    // every box inside BARN's 4.5 m corridor (scaled), on its 0.15 m grid (scaled)
    ASSERT_FALSE(s.terrain.boxes.empty()) << file;
    for (const sim::PlacedBox& box : s.terrain.boxes) {
      EXPECT_LE(std::abs(box.centre_W.x()) + box.half_extents_m.x(), 2.25 * kScale + 1e-3) << file;
      const double cells = 2.0 * box.half_extents_m.x() / (0.15 * kScale);
      EXPECT_NEAR(cells, std::round(cells), 1e-3) << file;
    }
  }
}

}  // namespace
}  // namespace trav::scenarios
