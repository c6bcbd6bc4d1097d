#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "common/input_error.h"
#include "scenarios/experiments/batch.h"
#include "scenarios/experiments/batch_report.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;

TEST(BatchFilesTest, TheShippedBatchesExpandToTheirRuns) {
  const fs::path scenarios = fs::path(TRAV_SOURCE_DIR) / "scenarios";
  const std::pair<const char*, std::size_t> batches[] = {
      {"batch/suite_seeds.yaml", 90}, {"batch/mappers.yaml", 40}, {"batch/mpc_horizon.yaml", 18},
      {"stress/density.yaml", 15},    {"stress/speed.yaml", 12},  {"stress/behaviour.yaml", 24},
      {"stress/ci.yaml", 4}};
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

}  // namespace
}  // namespace trav::scenarios
