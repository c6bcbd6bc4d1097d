// Every suite scenario (scenarios/suite/) over 10 terrain seeds: the generators keep the start and
// goal areas clear and the closed loop reaches the goal whatever the world looks like. One ctest
// per scenario and seed (label `seeds`), so that they run in parallel.
#include <unistd.h>

#include <filesystem>
#include <string>
#include <tuple>

#include <gtest/gtest.h>

#include "common/enum_names.h"
#include "scenarios/run/scenario.h"
#include "scenarios/run/scenario_run.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;

class SuiteSeedTest : public testing::TestWithParam<std::tuple<std::string, int>> {};

TEST_P(SuiteSeedTest, ReachesTheGoal) {
  const auto& [name, seed] = GetParam();
  Scenario scenario = LoadScenario(common::YamlDocument::Load(
      std::string(TRAV_SOURCE_DIR) + "/scenarios/suite/" + name + ".yaml"));
  scenario.terrain.seed = static_cast<std::uint64_t>(seed);
  const fs::path out = fs::temp_directory_path() / ("trav_seeds_" + std::to_string(getpid()) + "_" +
                                                    name + "_" + std::to_string(seed));
  fs::create_directories(out);
  const RunSummary summary =
      RunScenario(scenario, RobotModelPath(scenario, TRAV_MODELS_DIR), out.string());
  fs::remove_all(out);
  EXPECT_EQ(summary.outcome, Outcome::kSuccess)
      << name << " seed " << seed << ": " << common::NameOf(summary.outcome) << ", planner "
      << summary.navigation->last_planner_status
      << (summary.collision ? ", hit " + summary.collision->target : std::string());
}

INSTANTIATE_TEST_SUITE_P(
    Suite, SuiteSeedTest,
    testing::Combine(testing::Values("hilly", "forest", "ruin", "road", "indoor", "steep_hill",
                                     "narrow_passage", "crossing", "head_on"),
                     testing::Range(101, 111)),
    [](const testing::TestParamInfo<std::tuple<std::string, int>>& param_info) {
      return std::get<0>(param_info.param) + "_" + std::to_string(std::get<1>(param_info.param));
    });

}  // namespace
}  // namespace trav::scenarios
