#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <map>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/input_error.h"
#include "scenarios/experiments/batch.h"
#include "scenarios/experiments/batch_report.h"
#include "scenarios/run/scenario_run.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;

TEST(BatchFilesTest, TheShippedBatchesExpandToTheirRuns) {
  const fs::path scenarios = fs::path(TRAV_SOURCE_DIR) / "scenarios";
  const std::pair<const char*, std::size_t> batches[] = {
      {"batch/suite_seeds.yaml", 90}, {"batch/lidar_seeds.yaml", 60}, {"batch/mappers.yaml", 40},
      {"batch/mpc_horizon.yaml", 18}, {"stress/density.yaml", 15},    {"stress/speed.yaml", 12},
      {"stress/behaviour.yaml", 24},  {"stress/ci.yaml", 4},          {"probes/probes.yaml", 30},
      {"probes/round4.yaml", 30},     {"probes/round5.yaml", 30},     {"probes/round6.yaml", 30},
      {"probes/round7.yaml", 30},     {"probes/round8.yaml", 30},     {"probes/round9.yaml", 21}};
  for (const auto& [file, count] : batches) {
    const BatchSpec spec = LoadBatchFile((scenarios / file).string());
    EXPECT_EQ(ExpandBatch(spec).size(), count) << file;
  }
}

TEST(BatchFilesTest, RunsCrossEveryScenarioWithEveryValueLastAxisFastest) {
  const fs::path folder = fs::temp_directory_path() / ("batch_files_" + std::to_string(getpid()));
  fs::create_directories(folder);
  std::ofstream(folder / "a.yaml") << "name: a\nmode: drive\nlidar: {enabled: false}\n";
  std::ofstream(folder / "batch.yaml")
      << "scenarios: [a.yaml]\nsweep:\n  mapper: [em, sgp]\n  seeds: {first: 7, count: 2}\n"
         "  parameters: {duration: [5]}\nset: {physics.timestep: 0.001}\n";
  const BatchSpec spec = LoadBatchFile((folder / "batch.yaml").string());
  ASSERT_EQ(spec.axes.size(), 3u);
  const std::vector<BatchRun> runs = ExpandBatch(spec);
  ASSERT_EQ(runs.size(), 4u);
  EXPECT_EQ(runs[0].id, "a_mapper-em_seed-7_duration-5");
  EXPECT_EQ(runs[1].id, "a_mapper-em_seed-8_duration-5");
  EXPECT_EQ(runs[2].id, "a_mapper-sgp_seed-7_duration-5");
  EXPECT_EQ(runs[3].id, "a_mapper-sgp_seed-8_duration-5");
  EXPECT_NE(runs[3].scenario_yaml.find("timestep: 0.001"), std::string::npos);
  EXPECT_NE(runs[3].scenario_yaml.find("method: sgp"), std::string::npos);
  EXPECT_NE(runs[3].scenario_yaml.find("seed: 8"), std::string::npos);
  fs::remove_all(folder);
}

TEST(WilsonTest, MatchesTheTextbookInterval) {
  const WilsonInterval eight_of_ten = Wilson95(8, 10);
  EXPECT_NEAR(eight_of_ten.low, 0.4902, 1e-4);
  EXPECT_NEAR(eight_of_ten.high, 0.9433, 1e-4);
  const WilsonInterval all = Wilson95(2, 2);
  EXPECT_NEAR(all.low, 0.3424, 1e-4);
  EXPECT_DOUBLE_EQ(all.high, 1.0);
  EXPECT_DOUBLE_EQ(Wilson95(0, 0).low, 0.0);
  EXPECT_DOUBLE_EQ(Wilson95(0, 0).high, 1.0);
}

TEST(BatchRecordsTest, RunsAndResultsRoundTripThroughJson) {
  const BatchRunEntry entry{"a_seed-1", "a", {{"seed", "1"}, {"mapper", "em"}}};
  const nlohmann::json entry_json = entry;
  EXPECT_EQ(entry_json.dump(),
            R"({"id":"a_seed-1","parameters":{"mapper":"em","seed":"1"},"scenario":"a"})");
  EXPECT_EQ(nlohmann::json(entry_json.get<BatchRunEntry>()), entry_json);
  const BatchResult result{"a_seed-1", "a",  {{"seed", "1"}},
                           "success",  true, {{"distance_m", 2.5}}};
  const nlohmann::json result_json = result;
  EXPECT_EQ(result_json.dump(),
            R"({"id":"a_seed-1","metrics":{"distance_m":2.5},"outcome":"success",)"
            R"("parameters":{"seed":"1"},"scenario":"a","success":true})");
  EXPECT_EQ(nlohmann::json(result_json.get<BatchResult>()), result_json);
  EXPECT_THROW(nlohmann::json({{"id", "a"}}).get<BatchRunEntry>(), nlohmann::json::exception);
}

// The metrics `trav tune` accepts: every number of a summary.json with every section.
TEST(FlattenSummaryTest, ASummaryWithEverySectionHasEveryMetric) {
  std::set<std::string> expected;
  const auto add = [&](const std::string& section, std::initializer_list<const char*> names) {
    for (const char* name : names) expected.insert(section + name);
  };
  add("", {"sim_time_s", "wall_time_s", "real_time_factor", "distance_m", "max_roll_deg",
           "max_pitch_deg", "rms_roll_deg", "rms_pitch_deg", "physics_steps",
           "mujoco_warning_count", "video_frames", "lidar_frames", "lidar_points_per_frame",
           "lidar_ms_per_frame", "terrain.seed"});
  add("final_pose.", {"x", "y", "yaw"});
  add("mapping.", {"updates", "update_ms_median", "update_ms_max", "training_points_median",
                   "known_cells", "mean_error", "error_variance"});
  add("navigation.", {"goal_reached",
                      "time_to_goal_s",
                      "final_goal_distance_m",
                      "optimal_path_length_m",
                      "path_length_ratio",
                      "barn_score",
                      "rms_vertical_acceleration_m_s2",
                      "plans",
                      "failed_plans",
                      "replans_on_events",
                      "safety_stops",
                      "mover_tracking_error_m",
                      "perceived_mover_samples",
                      "false_mover_samples",
                      "near_misses",
                      "min_mover_clearance_m",
                      "path_length_m",
                      "fallbacks.wider_margin",
                      "fallbacks.follow_path",
                      "fallbacks.pose_search",
                      "fallbacks.turn_in_place",
                      "fallbacks.back_out",
                      "fallbacks.stop",
                      "give_ways",
                      "back_offs",
                      "step_climbs"});
  add("collision.", {"mover", "relative_speed_m_s", "robot_speed_m_s", "time_s"});
  add("localization.",
      {"final_position_error_m", "final_z_error_m", "final_yaw_error_deg", "max_position_error_m",
       "relative_error_10m_m", "relative_yaw_error_10m_deg", "relative_error_stretches"});
  add("tracking.", {"rms_lateral_error_m", "max_lateral_error_m", "rms_heading_error_rad",
                    "max_heading_error_rad", "rms_speed_error_m_s", "max_speed_error_m_s",
                    "rms_acceleration_command_m_s2", "rms_yaw_acceleration_command_rad_s2",
                    "solve_time_median_ms", "solve_time_p99_ms", "solve_time_max_ms",
                    "iterations_mean", "solves", "failures", "iteration_limits"});
  for (const char* module : {"lidar", "mapping", "planning", "control", "physics", "render"}) {
    add(std::string("compute.") + module + ".", {"calls", "median_ms", "max_ms", "total_s"});
  }
  std::set<std::string> metrics;
  for (const auto& [key, value] : FlattenSummary(nlohmann::json(SummaryWithEverySection()))) {
    metrics.insert(key);
  }
  EXPECT_EQ(metrics, expected);
  EXPECT_EQ(metrics.size(), 101u);
}

}  // namespace
}  // namespace trav::scenarios
