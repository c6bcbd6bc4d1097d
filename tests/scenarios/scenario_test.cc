#include "scenarios/run/scenario.h"

#include <cmath>
#include <map>
#include <memory>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/input_error.h"
#include "common/point_cloud.h"
#include "common/yaml_reader.h"
#include "mapping/traversability_mapper.h"
#include "scenarios/run/mappers.h"
#include "tests/cli_test_util.h"

namespace trav::scenarios {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

Scenario Load(const std::string& text) {
  return LoadScenario(common::YamlDocument::Parse(text, "test.yaml"));
}

TEST(ScenarioTest, BuiltInDefaultIsAThirtyMetreTraverseOfWoodedHillsWithVideo) {
  const Scenario dut =
      LoadScenario(common::YamlDocument::Parse(DefaultScenarioYaml(), "<built-in>"));
  EXPECT_EQ(dut.terrain.type, sim::TerrainType::kForest);
  EXPECT_EQ(dut.terrain.size_m, Eigen::Vector2d(50, 50));
  EXPECT_EQ(dut.terrain.resolution_m, 0.1);
  EXPECT_EQ(dut.mode, RunMode::kNavigate);
  EXPECT_EQ(dut.mapper, "fsgp-bgk");
  EXPECT_EQ(dut.planner_method, "astar");
  EXPECT_EQ((dut.goal_W - dut.start_W.position).norm(), 30.0);
  EXPECT_EQ(dut.expected_outcome, Outcome::kSuccess);
  EXPECT_TRUE(dut.video.enabled);
  EXPECT_EQ(dut.video.render.width, 1280);
}

// The planner names the mapper's layers it reads by string (planner/cost_map.h): a layer renamed on
// one side only would leave the planner without it (the faces' boxes: whole cells again).
TEST(ScenarioTest, ThePlannersReadLayersTheMappersWrite) {
  const Scenario dut =
      LoadScenario(common::YamlDocument::Parse(DefaultScenarioYaml(), "<built-in>"));
  const planner::CostMapConfig costs = dut.planner.SearchConfig();
  std::vector<std::string> read{costs.cost_layer, costs.speed.roughness_layer,
                                costs.slope.elevation_layer};
  read.insert(read.end(), costs.extent_layers.begin(), costs.extent_layers.end());
  const std::vector<std::string> written = mapping::layers::All();
  for (const std::string& layer : read) {
    EXPECT_THAT(written, ::testing::Contains(layer)) << layer;
  }
  EXPECT_TRUE(costs.obstacle_extents);
}

TEST(ScenarioTest, EveryKeyTakesEffect) {
  const Scenario dut = Load(R"(
schema_version: 1
name: every_key
terrain: {type: forest, seed: 9, size: [20, 30], resolution: 0.05,
          parameters: {family: swiss, octaves: 3, tree_density: 0.1, trunk_radius: [0.1, 0.2], canopy: false}}
robot: {model: /abs/robot.xml, start: [1, 2, 0.5], rollover_limit_deg: 45,
        skid_steer: {effective_track_factor: 2.0, max_speed: 2.0}}
physics: {timestep: 0.001, ground_friction: 0.7}
goal: [5, 6]
duration: 12
drive: [{v: 1, omega: 0.5, duration: 2}, {v: -0.5, duration: 1}]
video: {enabled: false, width: 320, height: 240, fps: 25, camera: overview, backend: egl, shadows: true, msaa: 4}
output: {dir: out/x}
expect: rolled_over
)");
  EXPECT_EQ(dut.name, "every_key");
  EXPECT_EQ(dut.terrain.type, sim::TerrainType::kForest);
  EXPECT_EQ(dut.terrain.seed, 9u);
  EXPECT_EQ(dut.terrain.size_m, Eigen::Vector2d(20, 30));
  EXPECT_EQ(dut.terrain.resolution_m, 0.05);
  EXPECT_EQ(dut.terrain.hilly.fractal.family, sim::FractalFamily::kSwiss);
  EXPECT_EQ(dut.terrain.hilly.fractal.octaves, 3);
  EXPECT_EQ(dut.terrain.forest.tree_density_per_m2, 0.1);
  EXPECT_EQ(dut.terrain.forest.trunk_radius_m[1], 0.2);
  EXPECT_FALSE(dut.terrain.forest.canopy);
  EXPECT_EQ(dut.robot_model, "/abs/robot.xml");
  EXPECT_EQ(dut.start_W.position, Eigen::Vector2d(1, 2));
  EXPECT_EQ(dut.start_W.yaw, 0.5);
  EXPECT_EQ(dut.rollover_limit_deg, 45.0);
  EXPECT_EQ(dut.skid_steer.effective_track_factor, 2.0);
  EXPECT_EQ(dut.skid_steer.max_speed_m_s, 2.0);
  EXPECT_EQ(dut.physics_timestep_s, 0.001);
  EXPECT_EQ(dut.ground_friction, 0.7);
  EXPECT_EQ(dut.goal_W, Eigen::Vector2d(5, 6));
  EXPECT_EQ(dut.duration_s, 12.0);
  ASSERT_EQ(dut.drive.size(), 2u);
  EXPECT_EQ(dut.drive[1].v_m_s, -0.5);
  EXPECT_EQ(dut.drive[1].omega_rad_s, 0.0);
  EXPECT_FALSE(dut.video.enabled);
  EXPECT_EQ(dut.video.render.width, 320);
  EXPECT_EQ(dut.video.fps, 25.0);
  EXPECT_EQ(dut.video.camera, renders::CameraMode::kOverview);
  EXPECT_EQ(dut.video.render.backend, renders::GlBackend::kEgl);
  EXPECT_TRUE(dut.video.render.shadows);
  EXPECT_EQ(dut.video.render.msaa_samples, 4);
  EXPECT_EQ(dut.output_dir, "out/x");
  EXPECT_EQ(dut.expected_outcome, Outcome::kRolledOver);
}

TEST(ScenarioTest, ResolvedYamlReloadsToTheSameScenario) {
  const Scenario original = Load(
      "terrain: {type: stairs, parameters: {num_steps: 3}}\nduration: 4\n"
      "drive: [{v: 0.5, duration: 4}]\n");
  const std::string resolved = ResolvedScenarioYaml(original);
  const Scenario reloaded = LoadScenario(common::YamlDocument::Parse(resolved, "resolved.yaml"));
  EXPECT_EQ(ResolvedScenarioYaml(reloaded), resolved);
  EXPECT_EQ(reloaded.terrain.stairs.num_steps, 3);
  EXPECT_THAT(resolved, HasSubstr("num_steps: 3"));
}

TEST(ScenarioTest, BadInputNamesSourceKeyAndValue) {
  EXPECT_THAT(
      [] { Load("terrain: {resolutoin: 0.1}"); },
      ThrowsMessage<common::InputError>(HasSubstr("test.yaml: terrain.resolutoin: unknown key")));
  EXPECT_THAT([] { Load("duration: long"); },
              ThrowsMessage<common::InputError>(
                  HasSubstr("test.yaml: duration: expected a finite number, got 'long'")));
  EXPECT_THAT([] { Load("terrain: {resolution: -0.1}"); },
              ThrowsMessage<common::InputError>(HasSubstr(
                  "test.yaml: terrain.resolution: value '-0.1' is outside its bounds [0.02, 1]")));
  EXPECT_THAT([] { Load("terrain: {type: swamp}"); },
              ThrowsMessage<common::InputError>(HasSubstr("terrain.type: unknown value 'swamp'")));
  EXPECT_THAT([] { Load("drive: [{v: 1, duration: 0}]"); },
              ThrowsMessage<common::InputError>(
                  HasSubstr("drive[0].duration: value '0' is outside its bounds [0.001, 86400]")));
  EXPECT_THAT([] { Load("schema_version: 2"); },
              ThrowsMessage<common::InputError>(
                  HasSubstr("schema_version: value '2' is outside its bounds [1, 1]")));
  EXPECT_THAT([] { Load("video: {width: 5}"); },
              ThrowsMessage<common::InputError>(
                  HasSubstr("test.yaml: video.width: value '5' is outside its bounds [16, 4096]")));
  EXPECT_THAT(
      [] { Load("terrain: {type: road, parameters: {family: fbm}}"); },
      ThrowsMessage<common::InputError>(HasSubstr("terrain.parameters.family: unknown key")));
}

TEST(ScenarioTest, MappingKeysTakeEffectAndAreChecked) {
  const Scenario dut = Load(R"(
mapping: {window: 8, resolution: 0.1, fuse: false, accumulate_frames: 4, variance_stride: 1,
          gp: {kernel: rational_quadratic, length_scales_xy: [0.2, 0.3], rq_alpha: 2.5},
          weight_curvature: 0.2, weight_gradient: 0.3, weight_slope: 0.5}
ground_truth: {clearance: 0.1}
)");
  EXPECT_EQ(dut.mapping.area.window_m, 8.0);
  EXPECT_EQ(dut.mapping.area.resolution_m, 0.1);
  EXPECT_FALSE(dut.mapping.fuse);
  EXPECT_EQ(dut.mapping.accumulate_frames, 4);
  EXPECT_EQ(dut.mapping.variance_stride, 1);
  EXPECT_EQ(dut.mapping.gp.kernel, mapping::KernelType::kRationalQuadratic);
  EXPECT_EQ(dut.mapping.gp.length_scales, Eigen::Vector4d(0.2, 0.3, 3.0, 3.0));
  EXPECT_EQ(dut.mapping.gp.rq_alpha, 2.5);
  EXPECT_EQ(dut.mapping.weight_slope, 0.5);
  EXPECT_EQ(dut.ground_truth.clearance_m, 0.1);
  EXPECT_THAT([] { Load("mapping: {weight_slope: 0.9}"); },
              ThrowsMessage<common::InputError>(HasSubstr(
                  "test.yaml: mapping.weights: value 1.525000 must be >= 0 and sum to 1")));
  EXPECT_THAT(
      [] { Load("mapping: {gp: {kernel: matern}}"); },
      ThrowsMessage<common::InputError>(HasSubstr("mapping.gp.kernel: unknown value 'matern'")));
}

TEST(ScenarioTest, StepCrossingKeysTakeEffectAndAreChecked) {
  const Scenario dut =
      Load("planner: {steps: {max_angle: 20, low_height: 0.05, full_height: 0.1}}");
  EXPECT_EQ(dut.planner.search.steps.max_angle_deg, 20.0);
  EXPECT_EQ(dut.planner.search.steps.low_height_m, 0.05);
  EXPECT_EQ(dut.planner.search.steps.full_height_m, 0.1);
  // the planner's footprint sets the reach
  EXPECT_EQ(dut.planner.SearchConfig().steps.reach_m, dut.planner.footprint.CircumscribedRadius());
  EXPECT_THAT(
      [] { Load("planner: {steps: {low_height: 0.1, full_height: 0.1}}"); },
      ThrowsMessage<common::InputError>(HasSubstr(
          "test.yaml: planner.steps.full_height: value 0.100000 must be > steps.low_height")));
  EXPECT_THAT([] { Load("planner: {steps: {max_angle: 0}}"); },
              ThrowsMessage<common::InputError>(
                  HasSubstr("planner.steps.max_angle: value 0.000000 must be in (0, 90]")));
}

TEST(ScenarioTest, StepClimbKeysTakeEffectAndAreChecked) {
  const Scenario dut = Load("navigation: {climb_speed: 0.9, climb_pitch: 8, climb_step: 0.1}");
  EXPECT_EQ(dut.navigation.climb_speed_m_s, 0.9);
  EXPECT_EQ(dut.navigation.climb_pitch_deg, 8.0);
  EXPECT_EQ(dut.navigation.climb_step_m, 0.1);
  EXPECT_EQ(Load("navigation: {climb_speed: 0}").navigation.climb_speed_m_s, 0.0);  // off
  EXPECT_THAT([] { Load("navigation: {climb_pitch: 0}"); },
              ThrowsMessage<common::InputError>(
                  HasSubstr("navigation.climb_pitch: value 0.000000 must be in (0, 90) deg")));
  EXPECT_THAT([] { Load("navigation: {climb_speed: -1}"); },
              ThrowsMessage<common::InputError>(HasSubstr("navigation.climb_speed")));
  EXPECT_THAT([] { Load("navigation: {climb_step: -0.1}"); },
              ThrowsMessage<common::InputError>(HasSubstr("navigation.climb_step")));
}

// M, the inducing points, is one key for every GP mapper: SGP takes it as well as FSGP-BGK.
TEST(ScenarioTest, EveryGpMapperTakesItsInducingPointsFromMaxTrainingPoints) {
  // a dense 10 x 10 m surface with a bump: more points than any M below
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i <= 100; ++i) {
    for (int j = 0; j <= 100; ++j) {
      const float x = -5.0f + 0.1f * static_cast<float>(i),
                  y = -5.0f + 0.1f * static_cast<float>(j);
      points.emplace_back(x, y, 0.2f * std::exp(-(x * x + y * y)));
    }
  }
  const common::PointCloud cloud = common::MakePointCloud(points);
  for (const char* method : {"sgp", "fsgp-bgk"}) {
    for (const int m : {50, 200}) {
      const Scenario scenario = Load(std::string("mapping: {method: ") + method +
                                     ", max_training_points: " + std::to_string(m) + "}");
      const std::unique_ptr<mapping::TraversabilityMapper> mapper = MakeMapper(scenario);
      const mapping::MapUpdateResult result =
          mapper->Update(cloud, Eigen::Isometry3d(Eigen::Translation3d(0, 0, 0.3)), 0.0);
      ASSERT_EQ(result.status, mapping::MapUpdateStatus::kUpdated) << method;
      // SGP: every floor(N / M)-th point, so M to 2 M of them; FSGP-BGK: at most M
      EXPECT_LE(result.training_points, std::string(method) == "sgp" ? 2 * m - 1 : m) << method;
      EXPECT_GE(result.training_points, std::string(method) == "sgp" ? m : m / 2) << method;
    }
  }
}

// A pose estimate whose height drifts raises the whole ground between two frames: on the true
// pose that rise is a step against the cells' floors, on an estimated one it is no obstacle.
TEST(ScenarioTest, AMapperOnAnEstimatedPoseTakesNoStepsAgainstTheFloors) {
  auto ground_at = [](float z) {
    std::vector<Eigen::Vector3f> points;
    for (int i = 0; i <= 100; ++i) {
      for (int j = 0; j <= 100; ++j) {
        points.emplace_back(-5.0f + 0.1f * static_cast<float>(i),
                            -5.0f + 0.1f * static_cast<float>(j), z);
      }
    }
    return common::MakePointCloud(points);
  };
  const double rise_m = 0.2;  // above mapping.max_step, 0.15
  const Scenario scenario = Load("mapping: {method: fsgp-bgk}");
  for (const MapperPose pose : {MapperPose::kTrue, MapperPose::kEstimated}) {
    const std::unique_ptr<mapping::TraversabilityMapper> mapper = MakeMapper(scenario, pose);
    mapper->Update(ground_at(0.0f), Eigen::Isometry3d(Eigen::Translation3d(0, 0, 0.3)), 0.0);
    mapper->Update(ground_at(static_cast<float>(rise_m)),
                   Eigen::Isometry3d(Eigen::Translation3d(0, 0, 0.3 + rise_m)), 0.1);
    const std::optional<float> cost =
        mapper->map().At(mapping::layers::kTraversability, Eigen::Vector2d(2.0, 1.0));
    ASSERT_TRUE(cost.has_value());
    EXPECT_EQ(*cost == 1.0f, pose == MapperPose::kTrue) << *cost;
  }
}

TEST(ScenarioTest, DriveCommandFollowsTheScriptAndStopsAfterIt) {
  const std::vector<DriveSegment> drive = {{1.0, 0.0, 2.0}, {0.5, -0.3, 1.0}};
  EXPECT_EQ(DriveCommandAt(drive, 0.0).v, 1.0);
  EXPECT_EQ(DriveCommandAt(drive, 1.999).v, 1.0);
  EXPECT_EQ(DriveCommandAt(drive, 2.0).omega, -0.3);
  EXPECT_EQ(DriveCommandAt(drive, 3.0).v, 0.0);
}

}  // namespace
}  // namespace trav::scenarios

namespace trav::scenarios {
namespace {

// The bounds in docs/scenario-format.md are the ones the loader checks: the table between the
// markers is ScenarioBoundsTable() as it is.
TEST(ScenarioBoundsTest, TheDocumentedBoundsAreTheCheckedOnes) {
  const std::string docs =
      test_util::ReadFile(std::string(TRAV_SOURCE_DIR) + "/docs/scenario-format.md");
  const std::string begin = "<!-- bounds:begin -->\n", end = "<!-- bounds:end -->";
  const std::size_t from = docs.find(begin), to = docs.find(end);
  ASSERT_NE(from, std::string::npos);
  ASSERT_NE(to, std::string::npos);
  EXPECT_EQ(docs.substr(from + begin.size(), to - from - begin.size()), ScenarioBoundsTable())
      << "update docs/scenario-format.md with the table above";
}

// The backticked names in `text`, a `prefix.{a, b}` group expanded to prefix.a and prefix.b.
std::vector<std::string> BacktickedNames(const std::string& text) {
  std::vector<std::string> names;
  static const std::regex kTicked("`([^`]*)`");
  for (std::sregex_iterator it(text.begin(), text.end(), kTicked), end; it != end; ++it) {
    const std::string name = (*it)[1];
    const std::size_t brace = name.find(".{");
    if (brace == std::string::npos || name.back() != '}') {
      names.push_back(name.substr(0, name.find(' ')));
      continue;
    }
    std::stringstream group(name.substr(brace + 2, name.size() - brace - 3));
    for (std::string leaf; std::getline(group >> std::ws, leaf, ',');) {
      names.push_back(name.substr(0, brace + 1) + leaf);
    }
  }
  return names;
}

// A key path matches a documented name with '*' standing for any text.
bool Matches(const std::string& pattern, const std::string& key) {
  const std::size_t star = pattern.find('*');
  if (star == std::string::npos) return pattern == key;
  const std::string head = pattern.substr(0, star), tail = pattern.substr(star + 1);
  return key.size() >= head.size() + tail.size() && key.compare(0, head.size(), head) == 0 &&
         key.compare(key.size() - tail.size(), tail.size(), tail) == 0;
}

// What the key table of docs/scenario-format.md documents: every key its rows name ("`a.b.c`,
// `d`" names a.b.c and a.b.d), the leaves a wildcard row ("`mapping.*`") lists in its meaning,
// and per sequence row ("`drive`") the words of its meaning, for the keys of its items.
struct DocumentedKeys {
  std::set<std::string> keys;
  std::map<std::string, std::string> sequence_rows;  // first key -> the row's meaning
};

DocumentedKeys ReadKeyTable(const std::string& docs) {
  DocumentedKeys documented;
  std::stringstream lines(docs.substr(0, docs.find("\n## ")));
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("| `", 0) != 0) continue;
    const std::size_t key_end = line.find(" | ", 2);
    const std::string key_cell = line.substr(2, key_end - 2);
    const std::string meaning = line.substr(line.rfind(" | ", line.size() - 3));
    const std::vector<std::string> names = BacktickedNames(key_cell);
    const std::string& first = names.front();
    const std::string parent =
        first.substr(0, first.rfind('.') == std::string::npos ? 0 : first.rfind('.') + 1);
    documented.sequence_rows[first] = meaning;
    for (const std::string& name : names) {
      const std::string key = name.find('.') != std::string::npos ? name : parent + name;
      if (key.find('*') == std::string::npos) {
        documented.keys.insert(key);
        continue;
      }
      for (const std::string& leaf : BacktickedNames(meaning)) {
        if (Matches(key, parent + leaf)) documented.keys.insert(parent + leaf);
      }
    }
  }
  return documented;
}

bool MentionsWord(const std::string& text, const std::string& word) {
  return std::regex_search(text, std::regex("\\b" + word + "\\b"));
}

// Every key the loader accepts is documented, so that a key cannot be added without its docs:
// docs/scenario-format.md names it in its key table, or (an item of a sequence) in its sequence's
// row, or (a terrain parameter) docs/terrains.md names it.
TEST(ScenarioKeysTest, EveryKeyIsDocumented) {
  const std::string docs_dir = std::string(TRAV_SOURCE_DIR) + "/docs/";
  const DocumentedKeys documented =
      ReadKeyTable(test_util::ReadFile(docs_dir + "scenario-format.md"));
  const std::string terrains = test_util::ReadFile(docs_dir + "terrains.md");
  const std::string parameters = "terrain.parameters.";
  std::vector<std::string> undocumented;
  for (const std::string& key : ScenarioKeys()) {
    bool found = documented.keys.count(key) > 0;
    if (key.rfind(parameters, 0) == 0) {
      found = terrains.find("`" + key.substr(parameters.size()) + "`") != std::string::npos;
    }
    const std::size_t item = key.find("[i].");
    if (!found && item != std::string::npos) {
      const auto row = documented.sequence_rows.find(key.substr(0, item));
      found =
          row != documented.sequence_rows.end() && MentionsWord(row->second, key.substr(item + 4));
    }
    if (!found) undocumented.push_back(key);
  }
  EXPECT_THAT(undocumented, testing::IsEmpty()) << "document these keys in docs/";
  EXPECT_GT(ScenarioKeys().size(), 200u);
}

// The check above has teeth: a key the docs do not name is found.
TEST(ScenarioKeysTest, TheDocsCheckFindsAnUndocumentedKey) {
  const DocumentedKeys documented = ReadKeyTable(
      "| `lidar.rate`, `frame_period` | 1 | x |\n| `mapping.*` | - | `window` 10, "
      "`gp.{kernel, noise_std}` |\n| `drive` | [] | `{v: [m/s], omega}` |\n");
  EXPECT_EQ(documented.keys,
            (std::set<std::string>{"drive", "lidar.rate", "lidar.frame_period", "mapping.window",
                                   "mapping.gp.kernel", "mapping.gp.noise_std"}));
  EXPECT_TRUE(MentionsWord(documented.sequence_rows.at("drive"), "omega"));
  EXPECT_FALSE(MentionsWord(documented.sequence_rows.at("drive"), "duration"));
}

TEST(ScenarioBoundsTest, EveryNumberOutsideItsBoundsOrNotFiniteIsBadInput) {
  auto load = [](const std::string& text) {
    return LoadScenario(common::YamlDocument::Parse("schema_version: 1\n" + text, "b.yaml"));
  };
  for (const char* text :
       {"duration: 1e308", "duration: .inf", "duration: .nan", "physics: {timestep: 1e-300}",
        "robot: {start: [.nan, 0, 0]}", "robot: {start: [0, 1e9, 0]}", "goal: [-.inf, 0]",
        "lidar: {mount: [0, 0, .nan, 0, 0, 0]}", "lidar: {rate: 1e9}",
        "traffic: {count: 2147483647}",
        "terrain: {type: road, parameters: {poles_per_block: 2147483647}}",
        "terrain: {size: [500, 500], resolution: 0.02}",
        "mapping: {map_size: 1000, resolution: 0.02}", "video: {fps: 1e-9}",
        "terrain: {type: stairs, parameters: {num_steps: 100000000}}",
        "terrain: {type: indoor, parameters: {furniture_per_room: 1000000}}",
        "track: {size: 1e300}"}) {
    EXPECT_THROW(load(text), common::InputError) << text;
  }
  EXPECT_NO_THROW(load("duration: 86400"));
}

}  // namespace
}  // namespace trav::scenarios
