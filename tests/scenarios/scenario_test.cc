#include "scenarios/run/scenario.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/input_error.h"
#include "common/yaml_reader.h"
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
  EXPECT_EQ(dut.mapper, MapperMethod::kFsgpBgk);
  EXPECT_EQ((dut.goal_W - dut.start_W.position).norm(), 30.0);
  EXPECT_EQ(dut.expected_outcome, Outcome::kSuccess);
  EXPECT_TRUE(dut.video.enabled);
  EXPECT_EQ(dut.video.render.width, 640);
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
