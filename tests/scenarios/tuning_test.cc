// End-to-end tests of `trav tune`: a known optimum, resuming, the MPC on tracking scenarios, and
// bad tuning files.
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/yaml_reader.h"
#include "tests/cli_test_util.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;
using test_util::CommandResult;
using test_util::ReadFile;
using test_util::RunTrav;
using ::testing::HasSubstr;

// Drives straight for 3 s at drive[0].v: the distance is 3 m for v a little above 1 m/s (the
// robot needs a moment to reach its speed).
constexpr char kDrive[] =
    "schema_version: 1\nname: drive\nmode: drive\nterrain: {type: flat, size: [20, 20]}\n"
    "robot: {start: [-5, 0, 0]}\ndrive: [{v: 0.5, omega: 0, duration: 3}]\nduration: 3\n"
    "lidar: {enabled: false}\nvideo: {enabled: false}\n";
constexpr char kDistanceTuning[] =
    "name: distance\nscenarios: [drive.yaml]\nseeds: [1]\nheld_out_seeds: [2]\n"
    "parameters:\n  drive[0].v: {min: 0.1, max: 2.0}\n"
    "objective:\n  distance_m: {weight: 1, target: 3.0}\nbudget: 15\n";

class TuningTest : public ::testing::Test {
 protected:
  void SetUp() override { root_ = test_util::FreshTestFolder("trav_tune_test"); }
  void TearDown() override { fs::remove_all(root_); }

  fs::path Write(const std::string& name, const std::string& text) const {
    std::ofstream(root_ / name) << text;
    return root_ / name;
  }
  CommandResult Tune(const fs::path& file, const std::string& extra = "") const {
    return RunTrav("tune " + file.string() + " --out " + (root_ / "out").string() + " " + extra);
  }

  fs::path root_;
};

TEST_F(TuningTest, FindsTheSpeedThatDrivesThreeMetresInThreeSeconds) {
  Write("drive.yaml", kDrive);
  const CommandResult run = Tune(Write("tune.yaml", kDistanceTuning));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const common::YamlDocument tuned =
      common::YamlDocument::Load((root_ / "out/tuned.yaml").string());
  const double v = std::stod(*tuned.Find("drive[0].v"));
  EXPECT_NEAR(v, 1.0, 0.05);  // 1 m/s plus what the acceleration costs
  const std::string report = ReadFile(root_ / "out/report.md");
  std::smatch objective;
  ASSERT_TRUE(std::regex_search(report, objective, std::regex(R"(\| tuned \| ([0-9.e-]+) \|)")));
  EXPECT_LT(std::stod(objective[1]), 0.02);                    // within 2 cm of 3 m
  EXPECT_THAT(report, HasSubstr("| scenario values | 1.52"));  // 0.5 m/s: 1.47 m
  EXPECT_THAT(report, HasSubstr("The tuned values lower the held-out objective"));
  if (access("/usr/bin/gnuplot", X_OK) == 0) {
    EXPECT_TRUE(fs::exists(root_ / "out/objective.png"));
    EXPECT_TRUE(fs::exists(root_ / "out/parameters.png"));
  }
}

TEST_F(TuningTest, SetOverridesEveryRunAfterTheTuningFile) {
  Write("drive.yaml", kDrive);
  const CommandResult run =
      Tune(Write("tune.yaml", kDistanceTuning), "--budget 2 --set duration=1.5");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  int scenarios = 0;
  for (const auto& entry : fs::recursive_directory_iterator(root_ / "out" / "candidates")) {
    if (entry.path().extension() != ".yaml") continue;
    EXPECT_THAT(ReadFile(entry.path()), HasSubstr("duration: 1.5")) << entry.path();
    ++scenarios;
  }
  EXPECT_GT(scenarios, 0);
}

TEST_F(TuningTest, ResumesFromTheRunsInTheFolder) {
  Write("drive.yaml", kDrive);
  const fs::path file = Write("tune.yaml", kDistanceTuning);
  ASSERT_EQ(Tune(file, "--budget 5").exit_code, 0);
  const std::string first = ReadFile(root_ / "out/evaluations.csv");
  const CommandResult again = Tune(file, "--budget 5");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_THAT(again.output, HasSubstr("5 evaluations (5 from the folder)"));
  EXPECT_EQ(ReadFile(root_ / "out/evaluations.csv"), first);
  // another tuning into the same folder is refused
  const fs::path other = Write("other.yaml", std::string(kDistanceTuning) + "seed: 4\n");
  const CommandResult refused = Tune(other, "--budget 5");
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_THAT(refused.output, HasSubstr("tune.json"));
}

TEST_F(TuningTest, TunesTheMpcOnTrackingScenariosAndComparesOnHeldOutSeeds) {
  const fs::path track = fs::path(TRAV_SOURCE_DIR) / "scenarios/track";
  const fs::path file =
      Write("mpc.yaml", "name: mpc\nscenarios: [" + (track / "figure_eight.yaml").string() + ", " +
                            (track / "slalom.yaml").string() +
                            "]\nseeds: [1]\nheld_out_seeds: [2]\nset: {duration: 8}\n"
                            "parameters:\n"
                            "  controller.mpc.state_weights[0]: {min: 5, max: 400, scale: log}\n"
                            "  controller.mpc.state_weights[1]: {min: 5, max: 400, scale: log}\n"
                            "objective:\n  tracking.rms_lateral_error_m: {weight: 100}\n"
                            "budget: 6\n");
  const CommandResult run = Tune(file);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string report = ReadFile(root_ / "out/report.md");
  std::smatch rows;
  ASSERT_TRUE(std::regex_search(
      report, rows,
      std::regex(
          R"(\| scenario values \| ([0-9.e-]+) \| ([0-9.e-]+) \|[^\n]*\n\| tuned \| ([0-9.e-]+) \| ([0-9.e-]+) \|)")))
      << report;
  const double default_training = std::stod(rows[1]), default_held_out = std::stod(rows[2]);
  const double tuned_training = std::stod(rows[3]), tuned_held_out = std::stod(rows[4]);
  EXPECT_LE(tuned_training, default_training);  // the search starts from the defaults
  // the verdict matches the held-out numbers
  if (tuned_held_out < default_held_out) {
    EXPECT_THAT(report, HasSubstr("The tuned values lower the held-out objective"));
  } else {
    EXPECT_THAT(report, HasSubstr("Tuning could not improve the held-out objective"));
  }
  EXPECT_THAT(ReadFile(root_ / "out/tuned.yaml"), HasSubstr("state_weights:"));
}

TEST_F(TuningTest, BadTuningFilesExitWithTwoNamingTheKey) {
  Write("drive.yaml", kDrive);
  const std::string head = "scenarios: [drive.yaml]\n";
  const std::string objective = "objective:\n  distance_m: {weight: 1}\n";
  const std::pair<std::string, std::string> cases[] = {
      {head + "parameters:\n  controller.mpc.nonsense: {min: 1, max: 2}\n" + objective,
       "parameters.controller.mpc.nonsense"},
      {head + "parameters:\n  drive[0].v: {min: 1, max: 1}\n" + objective, "an empty range"},
      {head + "parameters:\n  drive[0].v: {min: 0.1, max: 2}\n"
              "objective:\n  tracking.nonsense: {weight: 1}\n",
       "tracking.nonsense"},
      {head + "parameters:\n  drive[0].v: {min: 0.1, max: 2}\n" + objective + "budgett: 3\n",
       "budgett: unknown key"},
      {head + "parameters:\n  drive[0].v: {min: 0.1, max: 2}\n" + objective +
           "algorithm: annealing\n",
       "annealing"},
  };
  for (const auto& [text, named] : cases) {
    const CommandResult run = Tune(Write("bad.yaml", text));
    EXPECT_EQ(run.exit_code, 2) << text << run.output;
    EXPECT_THAT(run.output, HasSubstr(named)) << text;
    EXPECT_THAT(run.output, HasSubstr("bad.yaml")) << text;
    EXPECT_FALSE(fs::exists(root_ / "out")) << text;
  }
}

}  // namespace
}  // namespace trav::scenarios
