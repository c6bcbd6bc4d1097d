// End-to-end tests of `trav batch` on a local process pool: crashes and hangs recorded as outcomes,
// resuming after an interruption, the report, and bad batch files.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/stat.h>
#include <sys/wait.h>

#include "tests/cli_test_util.h"

extern char** environ;

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;
using test_util::CommandResult;
using test_util::ReadFile;
using test_util::RunTrav;
using ::testing::HasSubstr;

// A short tracking run on flat ground (no LiDAR, no video): about a second of wall time with
// `duration` simulated seconds.
std::string ShortScenario(const std::string& name, double duration, const std::string& extra = "") {
  return "schema_version: 1\nname: " + name +
         "\nmode: track\nterrain: {type: flat, size: [20, 20]}\nrobot: {start: [-6, 0, 0]}\n"
         "track: {reference: line, size: 12.0, speed: 1.0}\nduration: " +
         std::to_string(duration) + "\nlidar: {enabled: false}\nvideo: {enabled: false}\n" + extra;
}

class BatchTest : public ::testing::Test {
 protected:
  void SetUp() override { root_ = test_util::FreshTestFolder("trav_batch_test"); }
  void TearDown() override { fs::remove_all(root_); }

  fs::path Write(const std::string& name, const std::string& text) const {
    std::ofstream(root_ / name) << text;
    return root_ / name;
  }

  fs::path root_;
};

TEST_F(BatchTest, RecordsACrashAndAHangAsOutcomesAndFinishesTheOthers) {
  std::string list;
  for (int i = 1; i <= 6; ++i) {
    Write("ok" + std::to_string(i) + ".yaml", ShortScenario("ok" + std::to_string(i), 1.0));
    list += "ok" + std::to_string(i) + ".yaml, ";
  }
  Write("crash.yaml", ShortScenario("crash", 1.0, "test_fault: crash\n"));
  Write("hang.yaml", ShortScenario("hang", 1.0, "test_fault: hang\n"));
  // a limit far above a 1 s run's time on a loaded machine or under a sanitizer, so that only
  // the hang reaches it
  const fs::path batch =
      Write("batch.yaml", "scenarios: [" + list + "crash.yaml, hang.yaml]\ntime_limit: 20\n");
  setenv("TRAV_TEST_FAULTS", "1", 1);  // the fault hooks, inherited by the batch's runs

  const CommandResult run =
      RunTrav("batch " + batch.string() + " --out " + (root_ / "out").string() + " --jobs 2");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_THAT(run.output, HasSubstr("6 runs finished (0 kept from before), 2 failed"));

  const nlohmann::json results = nlohmann::json::parse(ReadFile(root_ / "out/results.json"));
  ASSERT_EQ(results.size(), 8u);
  std::map<std::string, std::string> outcomes;
  for (const nlohmann::json& row : results) outcomes[row.at("id")] = row.at("outcome");
  for (int i = 1; i <= 6; ++i) EXPECT_EQ(outcomes["ok" + std::to_string(i)], "completed");
  EXPECT_EQ(outcomes["crash"], "crashed");
  EXPECT_EQ(outcomes["hang"], "timed_out");
  for (const nlohmann::json& row : results) {
    if (row.at("outcome") == "completed") {
      EXPECT_TRUE(row.at("success").get<bool>());
      EXPECT_GT(row.at("metrics").at("tracking.solves").get<double>(), 0.0);
    }
  }
  const std::string report = ReadFile(root_ / "out/report.md");
  EXPECT_THAT(report, HasSubstr("| completed | 6 |"));
  EXPECT_THAT(report, HasSubstr("| crashed | 1 |"));
  EXPECT_THAT(report, HasSubstr("| timed_out | 1 |"));
  EXPECT_THAT(report, HasSubstr("| crash | crashed | logs/crash.log |"));
  EXPECT_THAT(ReadFile(root_ / "out/results.csv"), HasSubstr("hang,hang,timed_out,0"));
}

TEST_F(BatchTest, AnInterruptedBatchResumesWithoutRedoingFinishedRuns) {
  Write("line.yaml", ShortScenario("line", 8.0));
  const fs::path batch =
      Write("batch.yaml", "scenarios: [line.yaml]\nsweep: {seeds: {first: 1, count: 8}}\n");
  const fs::path out = root_ / "out";
  // start the batch, interrupt it once two runs have finished
  const std::string log = (root_ / "first.log").string();
  std::vector<std::string> args = {TRAV_BINARY, "batch", batch.string(), "--out", out.string(),
                                   "--jobs",    "1"};
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = -1;
  ASSERT_EQ(posix_spawn(&pid, TRAV_BINARY, &actions, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  // the runs committed under their final name, with their summary's inode: a run writes its
  // summary inside its partial folder ("<id>.partial-<pid>") before the rename, and the partial
  // folder of a run killed by the interrupt is not a finished run (the resumed batch removes it)
  auto committed = [&] {
    std::map<std::string, ino_t> inodes;
    std::error_code error;
    if (!fs::exists(out / "runs", error)) return inodes;
    for (const fs::directory_entry& entry : fs::directory_iterator(out / "runs")) {
      const std::string id = entry.path().filename().string();
      struct stat info {};
      if (id.find(".partial-") == std::string::npos &&
          stat((entry.path() / "summary.json").c_str(), &info) == 0) {
        inodes[id] = info.st_ino;
      }
    }
    return inodes;
  };
  auto finished = [&] { return static_cast<int>(committed().size()); };
  for (int i = 0; i < 600 && finished() < 2; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_GE(finished(), 2);
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1) << ReadFile(log);
  EXPECT_THAT(ReadFile(log), HasSubstr("interrupted"));
  const std::map<std::string, ino_t> inodes = committed();
  const int done_before = static_cast<int>(inodes.size());
  ASSERT_LT(done_before, 8);

  const CommandResult resumed =
      RunTrav("batch " + batch.string() + " --out " + out.string() + " --jobs 2");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_THAT(resumed.output,
              HasSubstr(std::to_string(done_before) + " of 8 runs already finished"));
  EXPECT_EQ(finished(), 8);
  for (const auto& [id, inode] : inodes) {
    struct stat info {};
    ASSERT_EQ(stat((out / "runs" / id / "summary.json").c_str(), &info), 0);
    EXPECT_EQ(info.st_ino, inode) << id << " was run again";
    EXPECT_THAT(resumed.output, ::testing::Not(HasSubstr("run " + id + " finished")));
  }
  EXPECT_EQ(nlohmann::json::parse(ReadFile(out / "results.json")).size(), 8u);
  // no half-written folder is left
  for (const fs::directory_entry& entry : fs::directory_iterator(out / "runs")) {
    EXPECT_EQ(entry.path().filename().string().find(".partial-"), std::string::npos);
  }
}

TEST_F(BatchTest, SweepsExpandToStableIdsAndTheReportPlotsNumericParameters) {
  Write("line.yaml", ShortScenario("line", 0.5));
  const fs::path batch = Write("batch.yaml",
                               "name: sweep\nscenarios: [line.yaml]\nsweep:\n  seed: [3, 4]\n"
                               "  parameters: {controller.mpc.horizon: [10, 20]}\n"
                               "set: {physics.timestep: 0.002}\n");
  // --set applies to every run after the file's `set`
  const CommandResult run =
      RunTrav("batch " + batch.string() + " --out " + (root_ / "out").string() +
              " --jobs 2 --set physics.timestep=0.001 --set goal=[5,1]");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  for (const std::string seed : {"3", "4"}) {
    for (const std::string horizon : {"10", "20"}) {
      const std::string id = "line_seed-" + seed + "_controller.mpc.horizon-" + horizon;
      EXPECT_TRUE(fs::exists(root_ / "out/runs" / id / "summary.json")) << id;
      const std::string scenario = ReadFile(root_ / "out/scenarios" / (id + ".yaml"));
      EXPECT_THAT(scenario, HasSubstr("horizon: " + horizon)) << id;
      EXPECT_THAT(scenario, HasSubstr("seed: " + seed)) << id;
      EXPECT_THAT(scenario, HasSubstr("timestep: 0.001")) << id;
      EXPECT_THAT(scenario, HasSubstr("goal: [5, 1]")) << id;
    }
  }
  const std::string csv = ReadFile(root_ / "out/vs_controller.mpc.horizon.csv");
  EXPECT_THAT(csv, HasSubstr("10,1,"));
  EXPECT_THAT(csv, HasSubstr("20,1,"));
  if (access("/usr/bin/gnuplot", X_OK) == 0) {
    EXPECT_TRUE(fs::exists(root_ / "out/success_vs_controller.mpc.horizon.png"));
  }
  EXPECT_THAT(ReadFile(root_ / "out/report.md"),
              HasSubstr("| line, controller.mpc.horizon=10 | 2 | 100 % (34-100) |"));

  // --collect rewrites the report from the folder alone
  fs::remove(root_ / "out/report.md");
  const CommandResult collect = RunTrav("batch --collect " + (root_ / "out").string());
  EXPECT_EQ(collect.exit_code, 0) << collect.output;
  EXPECT_TRUE(fs::exists(root_ / "out/report.md"));

  // the same folder with another batch is refused
  const fs::path other = Write("other.yaml", "scenarios: [line.yaml]\nsweep: {seed: [9]}\n");
  const CommandResult refused =
      RunTrav("batch " + other.string() + " --out " + (root_ / "out").string());
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_THAT(refused.output, HasSubstr("batch.json"));
}

TEST_F(BatchTest, BadBatchFilesExitWithTwoNamingTheKeyAndWriteNothing) {
  Write("line.yaml", ShortScenario("line", 0.5));
  const std::pair<std::string, std::string> cases[] = {
      {"scenarios: [line.yaml]\nsweeep: {seed: [1]}\n", "sweeep: unknown key"},
      {"scenarios: [line.yaml]\nsweep: {seed: []}\n", "sweep.seed"},
      {"scenarios: [line.yaml]\nsweep: {parameters: {controller.mpc.nonsense: [1, 2]}}\n",
       "controller.mpc.nonsense"},
      {"scenarios: []\n", "scenarios"},
      {"scenarios: [missing.yaml]\n", "missing.yaml"},
      {"scenarios: [line.yaml]\nsweep: {seed: [1]}\ntime_limit: -1\n", "time_limit"},
      {"scenarios: [line.yaml, line.yaml]\n", "two runs get the id 'line'"},
  };
  for (const auto& [text, named] : cases) {
    const fs::path batch = Write("bad.yaml", text);
    const CommandResult run =
        RunTrav("batch " + batch.string() + " --out " + (root_ / "out").string());
    EXPECT_EQ(run.exit_code, 2) << text << run.output;
    EXPECT_THAT(run.output, HasSubstr(named)) << text;
    EXPECT_THAT(run.output, HasSubstr("bad.yaml")) << text;
    EXPECT_FALSE(fs::exists(root_ / "out")) << text;
  }
}

}  // namespace
}  // namespace trav::scenarios
