// Ground from files: terrain type heightmap (a 16-bit PNG or a float32 .raw file, as `trav
// terrain` writes them, interpolated onto the terrain's grid: the round trip, the interpolation,
// the paths, every kind of bad file) and terrain type mesh (OBJ, STL, PLY: the top surface).
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

class TerrainFilesTest : public testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() / ("trav_terrain_files_" + std::to_string(getpid()));
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

  // A scenario of terrain `type` with `parameters` (YAML flow map) over `size`.
  static Scenario Load(const std::string& size, const std::string& resolution,
                       const std::string& parameters, const std::string& type = "heightmap") {
    return LoadScenario(common::YamlDocument::Parse(
        "schema_version: 1\nterrain: {type: " + type + ", size: " + size +
            ", resolution: " + resolution + ", parameters: " + parameters + "}\n",
        "test.yaml"));
  }

  // The InputError message of loading and generating the world, or "" when both work.
  static std::string LoadError(const std::string& parameters,
                               const std::string& type = "heightmap") {
    try {
      sim::GenerateTerrain(Load("[4, 2]", "1", parameters, type).terrain);
    } catch (const common::InputError& e) {
      return e.what();
    }
    return "";
  }

  // A text file in the test's folder; returns its path.
  std::string WriteText(const std::string& name, const std::string& text) const {
    const fs::path path = folder_ / name;
    std::ofstream(path) << text;
    return path.string();
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

TEST_F(TerrainFilesTest, ARawFileOfTheGridsSamplesGivesItsHeightsBitForBit) {
  const sim::TerrainWorld hills = Hills();
  const std::string raw = WriteRaw("hills.raw", hills.height_m);
  const Scenario scenario = Load("[12, 10]", "0.1", "{file: '" + raw + "', samples: [121, 101]}");
  const sim::TerrainWorld world = sim::GenerateTerrain(scenario.terrain);
  ASSERT_EQ(world.height_m.rows(), 121);
  ASSERT_EQ(world.height_m.cols(), 101);
  EXPECT_TRUE((world.height_m.array() == hills.height_m.array()).all());
  EXPECT_TRUE(world.obstacles.empty());
}

TEST_F(TerrainFilesTest, APngGivesTheHeightsWithinItsSixteenBitStep) {
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

TEST_F(TerrainFilesTest, OtherDimensionsAreInterpolatedBilinearlyOverTheSize) {
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

TEST_F(TerrainFilesTest, ARelativePathIsTakenFromTheScenarioFilesFolderAndMadeAbsolute) {
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

TEST_F(TerrainFilesTest, BadFilesAreBadInputNamingTheKeyAndTheFile) {
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

// The plane z = 0.1 x + 0.2 y + 0.3 over [-2, 2] x [-1, 1] as two triangles, in each format.
constexpr char kPlaneObj[] = "v -2 -1 -0.1\nv 2 -1 0.3\nv 2 1 0.7\nv -2 1 0.3\nf 1 2 3\nf 1 3 4\n";
constexpr char kPlaneQuadObj[] = "v -2 -1 -0.1\nv 2 -1 0.3\nv 2 1 0.7\nv -2 1 0.3\nf 1 2 3 4\n";
constexpr char kPlaneStl[] =
    "solid plane\n"
    "facet normal 0 0 1\nouter loop\nvertex -2 -1 -0.1\nvertex 2 -1 0.3\nvertex 2 1 0.7\n"
    "endloop\nendfacet\n"
    "facet normal 0 0 1\nouter loop\nvertex -2 -1 -0.1\nvertex 2 1 0.7\nvertex -2 1 0.3\n"
    "endloop\nendfacet\nendsolid plane\n";
constexpr char kPlanePly[] =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
    "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
    "-2 -1 -0.1\n2 -1 0.3\n2 1 0.7\n-2 1 0.3\n3 0 1 2\n3 0 2 3\n";

TEST_F(TerrainFilesTest, AMeshInEachFormatGivesItsSurfaceAtEverySample) {
  for (const auto& [name, text] :
       std::vector<std::pair<std::string, std::string>>{{"plane.obj", kPlaneObj},
                                                        {"quad.obj", kPlaneQuadObj},
                                                        {"plane.stl", kPlaneStl},
                                                        {"plane.ply", kPlanePly}}) {
    const std::string file = WriteText(name, text);
    const sim::TerrainWorld world =
        sim::GenerateTerrain(Load("[4, 2]", "0.5", "{file: '" + file + "'}", "mesh").terrain);
    ASSERT_EQ(world.height_m.rows(), 9) << name;
    ASSERT_EQ(world.height_m.cols(), 5) << name;
    for (int iy = 0; iy < 5; ++iy) {
      for (int ix = 0; ix < 9; ++ix) {
        const Eigen::Vector2d p = world.geometry.CellCenter(ix, iy);
        EXPECT_NEAR(world.height_m(ix, iy), 0.1 * p.x() + 0.2 * p.y() + 0.3, 1e-6)
            << name << " " << ix << " " << iy;
      }
    }
  }
}

TEST_F(TerrainFilesTest, TheTopSurfaceOfOverlappingTrianglesIsTheGround) {
  // a flat floor at 0 and a 1 m high roof over x in [0, 2]
  const std::string file =
      WriteText("roof.obj",
                "v -2 -1 0\nv 2 -1 0\nv 2 1 0\nv -2 1 0\nv 0 -1 1\nv 2 -1 1\nv 2 1 1\nv 0 1 1\n"
                "f 1 2 3\nf 1 3 4\nf 5 6 7\nf 5 7 8\n");
  const sim::TerrainWorld world =
      sim::GenerateTerrain(Load("[4, 2]", "1", "{file: '" + file + "'}", "mesh").terrain);
  Eigen::MatrixXf expected(5, 3);
  expected << 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1;
  EXPECT_EQ(world.height_m, expected);
}

TEST_F(TerrainFilesTest, BadMeshesAreBadInputNamingTheKeyAndTheFile) {
  EXPECT_THAT(LoadError("{}", "mesh"), HasSubstr("terrain.parameters.file: is required"));
  EXPECT_THAT(LoadError("{file: ground.dae}", "mesh"), HasSubstr("must end in .obj, .stl or .ply"));
  EXPECT_THAT(LoadError("{file: '" + (folder_ / "missing.obj").string() + "'}", "mesh"),
              HasSubstr("missing.obj"));
  const std::string text = WriteText("text.obj", "not a mesh\n");
  EXPECT_THAT(LoadError("{file: '" + text + "'}", "mesh"), HasSubstr("holds no triangle"));
  // half the world under no triangle
  const std::string half =
      WriteText("half.obj", "v 0 -1 0\nv 2 -1 0\nv 2 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n");
  EXPECT_THAT(LoadError("{file: '" + half + "'}", "mesh"),
              HasSubstr("terrain.parameters.file: '" + half +
                        "' leaves 6 of 15 height samples under no triangle"));
}

TEST(TerrainFilesExampleTest, TheShippedMeshIsTheRidgeItsScriptDescribes) {
  const Scenario scenario = LoadScenario(common::YamlDocument::Load(
      std::string(TRAV_SOURCE_DIR) + "/scenarios/terrain_files/mesh.yaml"));
  const sim::TerrainWorld world = sim::GenerateTerrain(scenario.terrain);
  // make_ridge.py: rolling ground 0.3 sin(0.25 x) cos(0.2 y), the ridge's crest 1.2 m beyond
  // |y| = 3.5 m and 0.1 m in the pass, on the mesh's vertices (every 0.5 m)
  auto ground = [](double x, double y) { return 0.3 * std::sin(0.25 * x) * std::cos(0.2 * y); };
  EXPECT_NEAR(world.GroundHeight({0.0, -8.0}), ground(0.0, -8.0) + 1.2, 1e-4);
  EXPECT_NEAR(world.GroundHeight({0.0, 0.0}), ground(0.0, 0.0) + 0.1, 1e-4);
  EXPECT_NEAR(world.GroundHeight({5.0, 5.0}), ground(5.0, 5.0), 1e-4);
}

TEST(TerrainFilesExampleTest, TheShippedHeightmapIsTheHillyWorldItWasWrittenFrom) {
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
