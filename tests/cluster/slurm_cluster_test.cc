// trav batch and trav eval on a real Slurm cluster: a one-node cluster (munge, slurmctld, slurmd
// from Debian, on loopback, in a temporary folder) started for the test and stopped after it.
// Skipped, with the reason, only where the daemons cannot start.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>

#include "tests/cli_test_util.h"
#include "tests/test_environment.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;
using test_util::CommandResult;
using test_util::ReadFile;
using test_util::RunTrav;
using ::testing::HasSubstr;
using ::testing::Not;

class SlurmClusterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("trav_slurm_test_" + std::to_string(getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
    const CommandResult start = test_util::RunCommand(std::string(CLUSTER_SCRIPT) + " start " +
                                                      (root_ / "cluster").string());
    if (start.exit_code != 0) {
      test_util::RunCommand(std::string(CLUSTER_SCRIPT) + " stop " + (root_ / "cluster").string());
      TRAV_SKIP_UNLESS_CI("the one-node Slurm cluster could not start: " + start.output);
    }
    started_ = true;
    setenv("SLURM_CONF", (root_ / "cluster/slurm.conf").c_str(), 1);
  }
  void TearDown() override {
    if (started_)
      test_util::RunCommand(std::string(CLUSTER_SCRIPT) + " stop " + (root_ / "cluster").string());
    unsetenv("SLURM_CONF");
    fs::remove_all(root_);
  }

  fs::path root_;
  bool started_{false};
};

TEST_F(SlurmClusterTest, BatchAndEvaluationRunAsJobArrays) {
  std::ofstream(root_ / "line.yaml")
      << "schema_version: 1\nname: line\nmode: track\nterrain: {type: flat, size: [20, 20]}\n"
         "robot: {start: [-6, 0, 0]}\ntrack: {reference: line, size: 12.0, speed: 1.0}\n"
         "duration: 1\nlidar: {enabled: false}\nvideo: {enabled: false}\n";
  std::ofstream(root_ / "batch.yaml") << "scenarios: [line.yaml]\nsweep: {seed: [1, 2, 3, 4]}\n";

  // a batch of 4 runs, one array task each, waited for and collected
  const fs::path out = root_ / "batch";
  const CommandResult batch = RunTrav("batch " + (root_ / "batch.yaml").string() + " --out " +
                                      out.string() + " --slurm --partition debug");
  ASSERT_EQ(batch.exit_code, 0) << batch.output;
  EXPECT_THAT(batch.output, HasSubstr("4 array tasks for 4 jobs"));
  // the settings went to sbatch as arguments: the script is one quoted command
  const std::string script = ReadFile(out / "slurm/job-0.sh");
  EXPECT_EQ(std::count(script.begin(), script.end(), '\n'), 2) << script;
  EXPECT_THAT(script, Not(HasSubstr("#SBATCH")));
  const nlohmann::json results = nlohmann::json::parse(ReadFile(out / "results.json"));
  ASSERT_EQ(results.size(), 4u);
  for (const nlohmann::json& row : results) EXPECT_EQ(row.at("outcome"), "completed");
  int task_logs = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(out / "logs")) {
    task_logs += entry.path().filename().string().rfind("slurm-", 0) == 0 ? 1 : 0;
  }
  EXPECT_EQ(task_logs, 4);

  // a value that would add a line to a script is refused before anything is written
  const CommandResult injected =
      RunTrav("batch " + (root_ / "batch.yaml").string() + " --out " + (root_ / "bad").string() +
              " --slurm --partition 'debug\ntouch " + (root_ / "pwned").string() + "'");
  EXPECT_EQ(injected.exit_code, 2) << injected.output;
  EXPECT_THAT(injected.output, HasSubstr("--partition"));
  EXPECT_FALSE(fs::exists(root_ / "bad"));
  EXPECT_FALSE(fs::exists(root_ / "pwned"));

  // submitted without waiting (two runs per task), then collected once the job has ended
  const fs::path later = root_ / "later";
  const CommandResult submitted = RunTrav("batch " + (root_ / "batch.yaml").string() + " --out " +
                                          later.string() + " --slurm --runs-per-task 2 --no-wait");
  ASSERT_EQ(submitted.exit_code, 0) << submitted.output;
  EXPECT_THAT(submitted.output, HasSubstr("2 array tasks for 4 jobs"));
  for (int i = 0; i < 600 && !test_util::RunCommand("squeue -h -o %i").output.empty(); ++i)
    usleep(100000);
  const CommandResult collected = RunTrav("batch --collect " + later.string());
  ASSERT_EQ(collected.exit_code, 0) << collected.output;
  EXPECT_THAT(collected.output, HasSubstr("4 runs with results"));

  // trav eval's scenes through the same machinery
  const fs::path eval = root_ / "eval";
  const CommandResult evaluated = RunTrav(
      "eval --out " + eval.string() +
      " --terrains flat --scenes 2 --frames 4 --methods ground-truth --no-ablation --slurm");
  ASSERT_EQ(evaluated.exit_code, 0) << evaluated.output;
  const nlohmann::json eval_results = nlohmann::json::parse(ReadFile(eval / "results.json"));
  ASSERT_EQ(eval_results.size(), 2u);  // the oracle, and the constant floor every table gets
  EXPECT_EQ(eval_results[0].at("method"), "ground-truth");
  EXPECT_EQ(eval_results[0].at("scenes"), 2);
  EXPECT_EQ(eval_results[0].at("mean_error").get<double>(), 0.0);
  EXPECT_EQ(eval_results[1].at("method"), "constant=0.5");
}

}  // namespace
}  // namespace trav::scenarios
