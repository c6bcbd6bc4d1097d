#include "scenarios/run/process_pool.h"

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;

ProcessTask Shell(const std::string& script, const std::string& log = "") {
  return {{"/bin/sh", "-c", script}, log};
}

TEST(ProcessPoolTest, RecordsHowEachTaskEndsAndRunsTheOthers) {
  const fs::path log = fs::temp_directory_path() / ("pool_test_" + std::to_string(getpid()));
  const std::vector<ProcessTask> tasks = {
      Shell("echo hello; echo oops >&2", log.string()),
      Shell("exit 3"),
      Shell("kill -SEGV $$"),
      Shell("sleep 30"),
      {{"/nonexistent/program"}, ""},
      Shell("exit 0"),
  };
  ProcessPoolOptions options;
  options.jobs = 2;
  options.time_limit_s = 2.0;  // far above a shell command's time on a loaded machine
  std::vector<std::size_t> order;
  const std::vector<ProcessResult> results = RunProcessPool(
      tasks, options, [&](std::size_t i, const ProcessResult&) { order.push_back(i); });
  ASSERT_EQ(results.size(), tasks.size());
  EXPECT_TRUE(results[0].succeeded());
  EXPECT_EQ(results[1].end, ProcessEnd::kExited);
  EXPECT_EQ(results[1].exit_code, 3);
  EXPECT_EQ(results[2].end, ProcessEnd::kSignaled);
  EXPECT_EQ(results[2].signal, SIGSEGV);
  EXPECT_EQ(results[3].end, ProcessEnd::kTimedOut);
  EXPECT_GE(results[3].wall_s, 2.0);
  EXPECT_EQ(results[4].end, ProcessEnd::kNotStarted);
  EXPECT_NE(results[4].message.find("/nonexistent/program"), std::string::npos);
  EXPECT_TRUE(results[5].succeeded());
  EXPECT_EQ(order.size(), tasks.size());  // every task reported once

  // standard output and error both go to the log
  std::ifstream file(log);
  std::stringstream text;
  text << file.rdbuf();
  EXPECT_EQ(text.str(), "hello\noops\n");
  fs::remove(log);
}

TEST(ProcessPoolTest, RunsAtMostJobsTasksAtOnce) {
  // each task appends its start and end to a file; with one job they never interleave
  const fs::path trace = fs::temp_directory_path() / ("pool_trace_" + std::to_string(getpid()));
  std::vector<ProcessTask> tasks;
  for (int i = 0; i < 3; ++i) {
    tasks.push_back(
        Shell("echo start >> " + trace.string() + "; sleep 0.05; echo end >> " + trace.string()));
  }
  const std::vector<ProcessResult> results = RunProcessPool(tasks, {1, 0.0});
  for (const ProcessResult& result : results) EXPECT_TRUE(result.succeeded());
  std::ifstream file(trace);
  std::stringstream text;
  text << file.rdbuf();
  EXPECT_EQ(text.str(), "start\nend\nstart\nend\nstart\nend\n");
  fs::remove(trace);
}

TEST(ProcessPoolTest, RejectsBadOptions) {
  EXPECT_THROW(RunProcessPool({}, {0, 0.0}), std::invalid_argument);
  EXPECT_THROW(RunProcessPool({}, {1, -1.0}), std::invalid_argument);
}

TEST(RunProcessTest, WaitsForTheExitStatus) {
  EXPECT_EQ(RunProcess(Shell("exit 7")).exit_code, 7);
  EXPECT_TRUE(RunProcess(Shell("true")).succeeded());
}

}  // namespace
}  // namespace trav::scenarios
