// Terrain type heightmap: ground read from a 16-bit PNG or a float32 .raw file, as `trav terrain`
// writes them, interpolated onto the terrain's grid; the round trip, the interpolation, the paths
// and every kind of bad file.
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/input_error.h"
#include "common/yaml_reader.h"
#include "renders/image.h"
#include "scenarios/run/scenario.h"
#include "scenarios/run/scenario_run.h"
#include "sim/terrain.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;
using testing::HasSubstr;

class HeightmapTerrainTest : public testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() / ("trav_heightmap_" + std::to_string(getpid()));
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }

  // float32 heights, x fastest, rows along +y (heightmap.raw of `trav terrain`).
  std::string WriteRaw(const std::string& name, const Eigen::MatrixXf& heights) const {
    const fs::path path = folder_ / name;
    std::ofstream file(path, std::ios::binary);
    file.write(reinterpret_cast<const char*>(heights.data()),
               static_cast<std::streamsize>(heights.size() * sizeof(float)));
    return path.string();
  }

  // 16-bit grayscale, top row = largest y, `low` -> 0 and `high` -> 65535.
  std::string WritePng(const std::string& name, const Eigen::MatrixXf& heights, float low,
                       float high) const {
    const auto num_x = static_cast<int>(heights.rows());
    const auto num_y = static_cast<int>(heights.cols());
    std::vector<std::uint16_t> values(static_cast<std::size_t>(num_x) * num_y);
    for (int row = 0; row < num_y; ++row) {
      for (int ix = 0; ix < num_x; ++ix) {
        values[static_cast<std::size_t>(row) * num_x + ix] = static_cast<std::uint16_t>(
            std::lround((heights(ix, num_y - 1 - row) - low) / (high - low) * 65535.0f));
      }
    }
    const fs::path path = folder_ / name;
    renders::WritePng16(path.string(), num_x, num_y, values);
    return path.string();
  }

  // A scenario of terrain type heightmap with `parameters` (YAML flow map) over `size`.
  static Scenario Load(const std::string& size, const std::string& resolution,
                       const std::string& parameters, const std::string& source = "test.yaml") {
    return LoadScenario(common::YamlDocument::Parse(
        "schema_version: 1\nterrain: {type: heightmap, size: " + size +
            ", resolution: " + resolution + ", parameters: " + parameters + "}\n",
        source));
  }

  // The InputError message of loading, or "" when it loads.
  static std::string LoadError(const std::string& parameters) {
    try {
      Load("[4, 2]", "1", parameters);
    } catch (const common::InputError& e) {
      return e.what();
    }
    return "";
  }

  fs::path folder_;
};

// A hilly world of 121 x 101 samples.
sim::TerrainWorld Hills() {
  sim::TerrainConfig config;
  config.type = sim::TerrainType::kHilly;
  config.seed = 3;
  config.size_m = Eigen::Vector2d(12.0, 10.0);
  config.resolution_m = 0.1;
  return sim::GenerateTerrain(config);
}

TEST_F(HeightmapTerrainTest, ARawFileOfTheGridsSamplesGivesItsHeightsBitForBit) {
  const sim::TerrainWorld hills = Hills();
  const std::string raw = WriteRaw("hills.raw", hills.height_m);
  const Scenario scenario = Load("[12, 10]", "0.1", "{file: '" + raw + "', samples: [121, 101]}");
  const sim::TerrainWorld world = sim::GenerateTerrain(scenario.terrain);
  ASSERT_EQ(world.height_m.rows(), 121);
  ASSERT_EQ(world.height_m.cols(), 101);
  EXPECT_TRUE((world.height_m.array() == hills.height_m.array()).all());
  EXPECT_TRUE(world.obstacles.empty());
}

TEST_F(HeightmapTerrainTest, APngGivesTheHeightsWithinItsSixteenBitStep) {
  const sim::TerrainWorld hills = Hills();
  const float low = hills.height_m.minCoeff();
  const float high = hills.height_m.maxCoeff();
  const std::string png = WritePng("hills.png", hills.height_m, low, high);
  const Scenario scenario = Load("[12, 10]", "0.1",
                                 "{file: '" + png + "', height_range: [" + std::to_string(low) +
                                     ", " + std::to_string(high) + "]}");
  const sim::TerrainWorld world = sim::GenerateTerrain(scenario.terrain);
  // half a step of 65535 over the range, plus the range printed to 6 decimals
  const double step = (high - low) / 65535.0;
  EXPECT_LE((world.height_m - hills.height_m).cwiseAbs().maxCoeff(), 0.5 * step + 2e-6);
}

TEST_F(HeightmapTerrainTest, OtherDimensionsAreInterpolatedBilinearlyOverTheSize) {
  // 3 x 2 samples over 4 x 2 m: the 5 x 3 grid's samples fall on halves of the file's
  Eigen::MatrixXf file(3, 2);
  file << 0.0f, 10.0f, 1.0f, 11.0f, 2.0f, 12.0f;
  const std::string raw = WriteRaw("tiny.raw", file);
  const sim::TerrainWorld world =
      sim::GenerateTerrain(Load("[4, 2]", "1", "{file: '" + raw + "', samples: [3, 2]}").terrain);
  Eigen::MatrixXf expected(5, 3);
  expected << 0.0f, 5.0f, 10.0f,  //
      0.5f, 5.5f, 10.5f,          //
      1.0f, 6.0f, 11.0f,          //
      1.5f, 6.5f, 11.5f,          //
      2.0f, 7.0f, 12.0f;
  EXPECT_TRUE(world.height_m.isApprox(expected, 1e-6f)) << world.height_m;
  EXPECT_FLOAT_EQ(world.GroundHeight(Eigen::Vector2d(2.0, 1.0)), 12.0f);
}

TEST_F(HeightmapTerrainTest, ARelativePathIsTakenFromTheScenarioFilesFolderAndMadeAbsolute) {
  Eigen::MatrixXf file(2, 2);
  file << 0.0f, 1.0f, 2.0f, 3.0f;
  WriteRaw("ground.raw", file);
  const fs::path scenario_path = folder_ / "ground.yaml";
  std::ofstream(scenario_path)
      << "schema_version: 1\nterrain: {type: heightmap, size: [2, 2], "
         "resolution: 1, parameters: {file: ground.raw, samples: [2, 2]}}\n";
  const Scenario scenario = LoadScenario(common::YamlDocument::Load(scenario_path.string()));
  EXPECT_EQ(scenario.terrain.heightmap.file, (folder_ / "ground.raw").string());
  // the resolved scenario names the absolute path, so it loads from anywhere
  EXPECT_THAT(ResolvedScenarioYaml(scenario), HasSubstr((folder_ / "ground.raw").string()));
  // 3 x 3 samples over 2 x 2 m: the centre is the mean, the corner the file's last sample
  EXPECT_FLOAT_EQ(sim::GenerateTerrain(scenario.terrain).height_m(1, 1), 1.5f);
  EXPECT_FLOAT_EQ(sim::GenerateTerrain(scenario.terrain).height_m(2, 2), 3.0f);
}

TEST_F(HeightmapTerrainTest, BadFilesAreBadInputNamingTheKeyAndTheFile) {
  EXPECT_THAT(LoadError("{}"), HasSubstr("terrain.parameters.file: is required"));
  EXPECT_THAT(LoadError("{file: '" + (folder_ / "missing.png").string() + "'}"),
              HasSubstr("terrain.parameters.file"));
  EXPECT_THAT(LoadError("{file: '" + (folder_ / "missing.png").string() + "'}"),
              HasSubstr("missing.png"));
  EXPECT_THAT(LoadError("{file: ground.tif}"), HasSubstr("must end in .png"));
  Eigen::MatrixXf file(3, 2);
  file.setZero();
  const std::string raw = WriteRaw("ground.raw", file);
  EXPECT_THAT(LoadError("{file: '" + raw + "'}"),
              HasSubstr("terrain.parameters.samples: must give"));
  EXPECT_THAT(LoadError("{file: '" + raw + "', samples: [2.5, 2]}"),
              HasSubstr("terrain.parameters.samples: must give"));
  EXPECT_THAT(LoadError("{file: '" + raw + "', samples: [3, 3]}"),
              HasSubstr("holds 24 bytes, not the 36 of 3 x 3 float32 samples"));
  file(0, 0) = std::nanf("");
  const std::string nan_raw = WriteRaw("nan.raw", file);
  EXPECT_THAT(LoadError("{file: '" + nan_raw + "', samples: [3, 2]}"), HasSubstr("not finite"));
  // a colour image is not a heightmap; a text file is not a PNG
  renders::Image colour;
  colour.width = colour.height = 2;
  colour.rgb.assign(12, 100);
  renders::WritePng((folder_ / "colour.png").string(), colour);
  EXPECT_THAT(LoadError("{file: '" + (folder_ / "colour.png").string() + "'}"),
              HasSubstr("must be a grayscale PNG"));
  std::ofstream(folder_ / "text.png") << "not a png";
  EXPECT_THAT(LoadError("{file: '" + (folder_ / "text.png").string() + "'}"),
              HasSubstr("not a readable PNG"));
}

TEST(HeightmapExampleTest, TheShippedHeightmapIsTheHillyWorldItWasWrittenFrom) {
  const Scenario scenario = LoadScenario(common::YamlDocument::Load(
      std::string(TRAV_SOURCE_DIR) + "/scenarios/terrain_files/heightmap.yaml"));
  sim::TerrainConfig hills;
  hills.type = sim::TerrainType::kHilly;
  hills.seed = 4;
  hills.size_m = Eigen::Vector2d(30.0, 30.0);
  hills.resolution_m = 0.1;
  hills.hilly.slope_p95_deg = 16.0;
  const sim::TerrainWorld original = sim::GenerateTerrain(hills);
  const sim::TerrainWorld world = sim::GenerateTerrain(scenario.terrain);
  const double step = (original.height_m.maxCoeff() - original.height_m.minCoeff()) / 65535.0;
  EXPECT_LE((world.height_m - original.height_m).cwiseAbs().maxCoeff(), 0.5 * step + 1e-6);
}

}  // namespace
}  // namespace trav::scenarios
