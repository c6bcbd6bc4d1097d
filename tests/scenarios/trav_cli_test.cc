// End-to-end tests of the trav command: exit codes, outputs, error messages, determinism.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>

#include "tests/cli_test_util.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;
using test_util::CommandResult;
using test_util::ReadFile;
using test_util::RunTrav;
using ::testing::HasSubstr;

class TravCliTest : public ::testing::Test {
 protected:
  void SetUp() override { root_ = test_util::FreshTestFolder("trav_cli_test"); }
  void TearDown() override { fs::remove_all(root_); }

  std::string WriteScenario(const std::string& name, const std::string& text) {
    const fs::path path = root_ / name;
    std::ofstream(path) << text;
    return path.string();
  }
  // The folder holds nothing but the scenario files: no output, complete or partial.
  void ExpectNoOutputFolder() {
    for (const auto& entry : fs::directory_iterator(root_)) {
      EXPECT_EQ(entry.path().extension(), ".yaml") << "left behind: " << entry.path();
    }
  }
  fs::path root_;
};

constexpr char kShortRun[] = R"(
schema_version: 1
name: short
terrain: {type: hilly, seed: 3, size: [12, 12], resolution: 0.1}
robot: {start: [-3, 0, 0]}
goal: [3, 0]
duration: 2
drive: [{v: 1.0, omega: 0.2, duration: 2}]
video: {enabled: false}
)";

TEST_F(TravCliTest, RunWritesSummaryTrajectoryAndResolvedScenario) {
  const std::string scenario = WriteScenario("short.yaml", kShortRun);
  const CommandResult result = RunTrav("run " + scenario + " --out " + (root_ / "run").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_THAT(result.output, HasSubstr("outcome: completed"));
  const nlohmann::json summary = nlohmann::json::parse(ReadFile(root_ / "run" / "summary.json"));
  EXPECT_EQ(summary["outcome"], "completed");
  EXPECT_NEAR(summary["sim_time_s"].get<double>(), 2.0, 1e-9);
  EXPECT_GT(summary["distance_m"].get<double>(), 1.5);
  EXPECT_LT(summary["distance_m"].get<double>(), 2.2);
  EXPECT_GT(summary["real_time_factor"].get<double>(), 0.0);
  for (const char* key :
       {"max_roll_deg", "max_pitch_deg", "rms_roll_deg", "rms_pitch_deg", "wall_time_s"}) {
    EXPECT_TRUE(summary.contains(key)) << key;
  }
  EXPECT_TRUE(summary["video"].is_null());
  EXPECT_TRUE(fs::exists(root_ / "run" / "scenario.yaml"));
  // 50 Hz samples over 2 s plus the header
  const std::string csv = ReadFile(root_ / "run" / "trajectory.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 101);
}

// --threads 2 (the default) maps on a second thread: the same maps as one thread, to the bit.
TEST_F(TravCliTest, TheMappingThreadChangesNothingButTheWallTime) {
  const std::string scenario = WriteScenario("short.yaml", kShortRun);
  for (const char* threads : {"1", "2"}) {
    const CommandResult result = RunTrav("run " + scenario + " --threads " + threads + " --out " +
                                         (root_ / threads).string());
    ASSERT_EQ(result.exit_code, 0) << result.output;
  }
  const nlohmann::json one = nlohmann::json::parse(ReadFile(root_ / "1" / "summary.json"));
  const nlohmann::json two = nlohmann::json::parse(ReadFile(root_ / "2" / "summary.json"));
  EXPECT_EQ(one["mapping"]["updates"], 19);
  for (const char* key : {"updates", "known_cells", "mean_error", "error_variance"}) {
    EXPECT_EQ(one["mapping"][key], two["mapping"][key]) << key;
  }
  EXPECT_EQ(ReadFile(root_ / "1" / "trajectory.csv"), ReadFile(root_ / "2" / "trajectory.csv"));
  EXPECT_EQ(RunTrav("run " + scenario + " --threads 3 --out " + (root_ / "3").string()).exit_code,
            2);
  EXPECT_FALSE(fs::exists(root_ / "3"));
}

TEST_F(TravCliTest, SeededRunsAreBitIdentical) {
  const std::string scenario = WriteScenario("short.yaml", kShortRun);
  ASSERT_EQ(RunTrav("run " + scenario + " --out " + (root_ / "a").string()).exit_code, 0);
  ASSERT_EQ(RunTrav("run " + scenario + " --out " + (root_ / "b").string()).exit_code, 0);
  EXPECT_EQ(ReadFile(root_ / "a" / "trajectory.csv"), ReadFile(root_ / "b" / "trajectory.csv"));
  ASSERT_EQ(RunTrav("run " + scenario + " --seed 4 --out " + (root_ / "c").string()).exit_code, 0);
  EXPECT_NE(ReadFile(root_ / "a" / "trajectory.csv"), ReadFile(root_ / "c" / "trajectory.csv"));
}

TEST_F(TravCliTest, UnexpectedOutcomeExitsWithOne) {
  const std::string scenario =
      WriteScenario("short.yaml", std::string(kShortRun) + "expect: rolled_over\n");
  const CommandResult result = RunTrav("run " + scenario + " --out " + (root_ / "run").string());
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_THAT(result.output, HasSubstr("outcome: completed (expected rolled_over)"));
  EXPECT_TRUE(fs::exists(root_ / "run" / "summary.json"));
}

TEST_F(TravCliTest, SetOverridesScenarioValues) {
  const std::string scenario = WriteScenario("short.yaml", kShortRun);
  const CommandResult result =
      RunTrav("run " + scenario + " --set duration=1 --set name=overridden --out " +
              (root_ / "run").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json summary = nlohmann::json::parse(ReadFile(root_ / "run" / "summary.json"));
  EXPECT_NEAR(summary["sim_time_s"].get<double>(), 1.0, 1e-9);
  EXPECT_EQ(summary["scenario"], "overridden");
}

TEST_F(TravCliTest, UnknownKeyIsBadInputWithNoOutput) {
  const std::string scenario = WriteScenario("bad.yaml", std::string(kShortRun) + "durration: 3\n");
  const CommandResult result = RunTrav("run " + scenario + " --out " + (root_ / "run").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.output, HasSubstr(scenario + ": durration: unknown key"));
  ExpectNoOutputFolder();
}

TEST_F(TravCliTest, WrongTypeIsBadInputNamingKeyAndValue) {
  std::string text = kShortRun;
  text.replace(text.find("goal: [3, 0]"), 12, "goal: here");
  const std::string scenario = WriteScenario("bad.yaml", text);
  const CommandResult result = RunTrav("run " + scenario + " --out " + (root_ / "run").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.output, HasSubstr("goal: expected a sequence of 2 numbers, got 'here'"));
  ExpectNoOutputFolder();
}

TEST_F(TravCliTest, DuplicateKeyIsBadInput) {
  const std::string scenario = WriteScenario("bad.yaml", std::string(kShortRun) + "duration: 5\n");
  const CommandResult result = RunTrav("run " + scenario + " --out " + (root_ / "run").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.output, HasSubstr(scenario + ": duration: duplicate key"));
  ExpectNoOutputFolder();
}

TEST_F(TravCliTest, NegativeResolutionIsBadInput) {
  const std::string scenario = WriteScenario("short.yaml", kShortRun);
  const CommandResult result = RunTrav("run " + scenario + " --set terrain.resolution=-0.2 --out " +
                                       (root_ / "run").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.output,
              HasSubstr("terrain.resolution: value '-0.2' is outside its bounds [0.02, 1]"));
  ExpectNoOutputFolder();
}

TEST_F(TravCliTest, MissingFilesAreBadInput) {
  CommandResult result =
      RunTrav("run " + (root_ / "missing.yaml").string() + " --out " + (root_ / "run").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.output,
              HasSubstr("missing.yaml: cannot open YAML file: No such file or directory"));
  const std::string scenario = WriteScenario("short.yaml", std::string(kShortRun) + "");
  result = RunTrav("run " + scenario + " --set robot.model=nothere.xml --out " +
                   (root_ / "run").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.output,
              HasSubstr("nothere.xml: robot.model: cannot open robot model: No such file or "
                        "directory"));
  ExpectNoOutputFolder();
}

TEST_F(TravCliTest, UsageErrorsExitWithTwo) {
  EXPECT_EQ(RunTrav("run --no-such-flag").exit_code, 2);
  EXPECT_EQ(RunTrav("fly").exit_code, 2);
  EXPECT_EQ(RunTrav("-v terrain --help").exit_code, 0);
  EXPECT_EQ(RunTrav("run --set nokeyvalue --out " + (root_ / "run").string()).exit_code, 2);
  const CommandResult help = RunTrav("run --help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_THAT(help.output, HasSubstr("--no-video"));
  ExpectNoOutputFolder();
}

TEST_F(TravCliTest, VersionNamesTravAndTheLibrariesThatDecideARun) {
  const CommandResult result = RunTrav("--version");
  EXPECT_EQ(result.exit_code, 0);
  EXPECT_THAT(result.output, HasSubstr("trav 0.1.0 (commit "));
  EXPECT_THAT(result.output, HasSubstr("MuJoCo 2.2.2, Embree "));
}

TEST_F(TravCliTest, ANegativeSeedIsBadInputAndVerboseWorksAfterTheSubcommand) {
  const std::string scenario = WriteScenario("short.yaml", kShortRun);
  for (const char* seed : {"-1", "x7", "1.5"}) {
    const CommandResult result =
        RunTrav("run " + scenario + " --seed=" + seed + " --out " + (root_ / "run").string());
    EXPECT_EQ(result.exit_code, 2) << seed;
    EXPECT_THAT(
        result.output,
        HasSubstr(std::string("--seed: expected a seed (a non-negative integer), got ") + seed));
  }
  EXPECT_EQ(RunTrav("eval --seed=-1 --out " + (root_ / "eval").string()).exit_code, 2);
  ExpectNoOutputFolder();
  const CommandResult verbose =
      RunTrav("run " + scenario + " -v --seed 4 --out " + (root_ / "run").string());
  EXPECT_EQ(verbose.exit_code, 0) << verbose.output;
}

TEST_F(TravCliTest, CalibrateWritesItsTableWithOut) {
  const CommandResult result = RunTrav("calibrate --out " + (root_ / "calibration").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const std::string csv = ReadFile(root_ / "calibration" / "calibration.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "commanded_v_m_s,commanded_omega_rad_s,measured_v_m_s,measured_omega_rad_s");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 7);  // a header and six samples
  const nlohmann::json summary =
      nlohmann::json::parse(ReadFile(root_ / "calibration" / "calibration.json"));
  EXPECT_EQ(summary.at("samples").size(), 6u);
  EXPECT_EQ(summary.at("effective_track_factor_used"), 2.48);
  EXPECT_NEAR(summary.at("effective_track_factor").get<double>(), 2.48, 0.25);
  EXPECT_THAT(result.output,
              HasSubstr(fmt::format("effective_track_factor that matches the commanded yaw rates: "
                                    "{:.3f}",
                                    summary.at("effective_track_factor").get<double>())));
}

TEST_F(TravCliTest, PatternComparesTheShippedTableWithTheProceduralModelAndAUsersTable) {
  // a user's table: the shipped table's first 8 rows, so its frame repeats them
  const fs::path table = root_ / "eight_rows.csv";
  std::ofstream(table) << "Time/s,Azimuth/deg,Zenith/deg\n1,268.99,37.838\n2,269.0,40.825\n"
                          "3,269.0,43.581\n4,269.0,46.152\n5,267.82,37.84\n6,267.77,40.825\n"
                          "7,267.72,43.58\n8,267.67,46.15\n";
  const CommandResult result = RunTrav("pattern --frames 3 --table " + table.string() + " --out " +
                                       (root_ / "pattern").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json report =
      nlohmann::json::parse(ReadFile(root_ / "pattern" / "pattern_statistics.json"));
  EXPECT_EQ(report.at("rays_per_frame"), 20000);
  const nlohmann::json& mid360 = report.at("patterns").at("mid360");
  EXPECT_EQ(mid360.at("elevation_total_variation_vs_mid360"), 0.0);
  // the table's two frames and the turned third keep filling the field
  const auto coverage = mid360.at("coverage_by_frames").get<std::vector<double>>();
  ASSERT_EQ(coverage.size(), 3u);
  EXPECT_LT(coverage[0], coverage[1]);
  EXPECT_LT(coverage[1], coverage[2]);
  EXPECT_GT(coverage[0], 0.6);
  // the procedural model differs from the table by a few per cent of its rays in elevation
  EXPECT_GT(report["patterns"]["procedural"]["elevation_total_variation_vs_mid360"], 0.02);
  // eight rows cover eight cells at most, in three elevation bands
  const nlohmann::json& user = report.at("patterns").at("table");
  EXPECT_LE(user.at("one_frame").at("covered_cells").get<int>(), 8);
  EXPECT_EQ(user.at("coverage_by_frames")[0], user.at("coverage_by_frames")[2]);
  const std::string rays = ReadFile(root_ / "pattern" / "pattern_rays.csv");
  EXPECT_EQ(rays.substr(0, rays.find('\n')),
            "azimuth_mid360,elevation_mid360,azimuth_procedural,elevation_procedural,"
            "azimuth_table,elevation_table");
  EXPECT_EQ(std::count(rays.begin(), rays.end(), '\n'), 20001);
  // bad input: exit 2 naming the file and line, or the flag, and nothing written
  std::ofstream(root_ / "bad.csv") << "Time/s,Azimuth/deg,Zenith/deg\n1,0,190\n";
  const CommandResult bad = RunTrav("pattern --table " + (root_ / "bad.csv").string() + " --out " +
                                    (root_ / "bad").string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_THAT(bad.output, HasSubstr("bad.csv: line 2"));
  EXPECT_FALSE(fs::exists(root_ / "bad"));
  EXPECT_EQ(RunTrav("pattern --frames 0 --out " + (root_ / "bad").string()).exit_code, 2);
  EXPECT_FALSE(fs::exists(root_ / "bad"));
}

TEST_F(TravCliTest, RunReportsLidarFramesAndRecordsClouds) {
  const std::string scenario = WriteScenario("short.yaml", kShortRun);
  const CommandResult result =
      RunTrav("run " + scenario + " --record-clouds --out " + (root_ / "run").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json summary = nlohmann::json::parse(ReadFile(root_ / "run" / "summary.json"));
  EXPECT_EQ(summary["lidar_frames"], 20);
  EXPECT_GT(summary["lidar_points_per_frame"].get<double>(), 1000.0);
  EXPECT_TRUE(fs::exists(root_ / "run" / "clouds" / "frame_000000.pcd"));
  EXPECT_TRUE(fs::exists(root_ / "run" / "clouds" / "frame_000019.pcd"));
}

TEST_F(TravCliTest, RunMapsTheLidarFramesAndScoresTheMapAgainstTheGroundTruth) {
  const std::string scenario = WriteScenario("short.yaml", kShortRun);
  for (const char* method : {"fsgp-bgk", "em"}) {
    const CommandResult result = RunTrav("run " + scenario + " --set mapping.method=" + method +
                                         " --out " + (root_ / method).string());
    ASSERT_EQ(result.exit_code, 0) << result.output;
    const nlohmann::json summary = nlohmann::json::parse(ReadFile(root_ / method / "summary.json"));
    const nlohmann::json& mapping = summary["mapping"];
    EXPECT_EQ(mapping["method"], method);
    // 20 frames in 2 s; the last one's map would take effect 0.05 s (navigation.mapping_latency)
    // after the run's end
    EXPECT_EQ(mapping["updates"], 19);
    EXPECT_GT(mapping["known_cells"].get<int>(), 500);
    EXPECT_LT(mapping["mean_error"].get<double>(), 0.15) << method;
    EXPECT_TRUE(fs::exists(root_ / method / "map.png"));
    EXPECT_TRUE(fs::exists(root_ / method / "map_ground_truth.png"));
  }
  const CommandResult off =
      RunTrav("run " + scenario + " --set mapping.enabled=false --out " + (root_ / "off").string());
  ASSERT_EQ(off.exit_code, 0);
  EXPECT_FALSE(nlohmann::json::parse(ReadFile(root_ / "off" / "summary.json")).contains("mapping"));
}

TEST_F(TravCliTest, ScanWritesTheRequestedFrames) {
  const std::string scenario = WriteScenario("short.yaml", kShortRun);
  const CommandResult result =
      RunTrav("scan " + scenario + " --frames 3 --out " + (root_ / "scan").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  int frames = 0;
  for (const auto& entry : fs::directory_iterator(root_ / "scan" / "clouds")) {
    ++frames;
    // Livox's fields: time offset, line, reflectivity and tag
    const std::string pcd = ReadFile(entry.path());
    EXPECT_THAT(pcd, HasSubstr("FIELDS x y z time line reflectivity tag\nSIZE 4 4 4 4 2 1 1\n"));
  }
  EXPECT_EQ(frames, 3);
  EXPECT_FALSE(fs::exists(root_ / "scan" / "video.mp4"));
}

TEST_F(TravCliTest, BadLidarSettingsAreBadInput) {
  const std::string scenario = WriteScenario("short.yaml", kShortRun);
  CommandResult result =
      RunTrav("run " + scenario + " --set lidar.table=" + (root_ / "none.csv").string() +
              " --out " + (root_ / "run").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.output, HasSubstr("none.csv: cannot open scan table"));
  const std::string table =
      WriteScenario("table.yaml", "Time/s,Azimuth/deg,Zenith/deg\n1,0,oops\n");
  result = RunTrav("run " + scenario + " --set lidar.table=" + table + " --out " +
                   (root_ / "run").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.output, HasSubstr("table.yaml: line 2"));
  result =
      RunTrav("run " + scenario + " --set lidar.range_max=-5 --out " + (root_ / "run").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.output, HasSubstr("lidar.range_max: value '-5' is outside its bounds"));
  result = RunTrav("run " + scenario + " --set lidar.rate=0 --out " + (root_ / "run").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.output, HasSubstr("lidar.rate: value '0' is outside its bounds"));
  ExpectNoOutputFolder();
}

TEST_F(TravCliTest, TerrainExportsHeightmapCloudAndPreview) {
  const std::string scenario = WriteScenario("short.yaml", kShortRun);
  const CommandResult result =
      RunTrav("terrain " + scenario + " --out " + (root_ / "terrain").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  for (const char* file :
       {"heightmap.png", "heightmap.raw", "cloud.pcd", "preview.png", "terrain.json"}) {
    EXPECT_TRUE(fs::exists(root_ / "terrain" / file)) << file;
  }
  // 121 x 121 float samples
  EXPECT_EQ(fs::file_size(root_ / "terrain" / "heightmap.raw"), 121u * 121u * 4u);
  const nlohmann::json terrain =
      nlohmann::json::parse(ReadFile(root_ / "terrain" / "terrain.json"));
  EXPECT_EQ(terrain["grid"]["num_x"], 121);
  EXPECT_EQ(terrain["type"], "hilly");
  // both ground truths on the map's 0.2 m grid (61 x 61 cells)
  for (const char* truth : {"ground_truth", "physical_truth"}) {
    EXPECT_TRUE(fs::exists(root_ / "terrain" / (std::string(truth) + ".png"))) << truth;
    EXPECT_EQ(fs::file_size(root_ / "terrain" / (std::string(truth) + ".raw")), 61u * 61u * 4u)
        << truth;
  }
  // a PCD header announcing the ground samples
  const std::string pcd = ReadFile(root_ / "terrain" / "cloud.pcd");
  EXPECT_THAT(pcd, HasSubstr("POINTS 14641"));
  EXPECT_THAT(pcd, HasSubstr("DATA binary"));
}

}  // namespace
}  // namespace trav::scenarios
