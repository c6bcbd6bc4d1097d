#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "common/enum_names.h"

namespace trav::scenarios {

/// A command run as a child process.
struct ProcessTask {
  /// The program and its arguments; argv[0] is a path, or a name looked up on the PATH.
  std::vector<std::string> argv;
  /// File that receives the task's standard output and error (truncated first); empty: both go
  /// to /dev/null. Standard input is always /dev/null.
  std::string log_path;
};

/// How a task ended.
enum class ProcessEnd {
  kExited,      ///< it exited by itself (see exit_code)
  kSignaled,    ///< a signal killed it (a crash, an out-of-memory kill; see signal)
  kTimedOut,    ///< it ran past the time limit and was killed
  kNotStarted,  ///< it could not be started (see message)
  kCancelled,   ///< the pool was interrupted (SIGINT or SIGTERM) before the task finished
};

/// The names of ProcessEnd's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<ProcessEnd>, 5> kProcessEndNames{
    {{ProcessEnd::kExited, "exited"},
     {ProcessEnd::kSignaled, "signaled"},
     {ProcessEnd::kTimedOut, "timed_out"},
     {ProcessEnd::kNotStarted, "not_started"},
     {ProcessEnd::kCancelled, "cancelled"}}};
constexpr const auto& EnumNames(ProcessEnd) { return kProcessEndNames; }

/// The end of one task.
struct ProcessResult {
  ProcessEnd end{ProcessEnd::kExited};
  int exit_code{0};     ///< kExited: the exit status
  int signal{0};        ///< kSignaled: the signal number
  double wall_s{0.0};   ///< from start to end [s]
  std::string message;  ///< kNotStarted: why

  [[nodiscard]] bool succeeded() const { return end == ProcessEnd::kExited && exit_code == 0; }
};

/// Settings of a pool.
struct ProcessPoolOptions {
  int jobs{1};               ///< tasks running at once, >= 1
  double time_limit_s{0.0};  ///< wall time allowed per task [s]; 0: unlimited
};

/// Called on the pool's thread as each task ends, with the task's index in the list.
using ProcessDoneCallback = std::function<void(std::size_t index, const ProcessResult& result)>;

/// Runs `tasks` as child processes, at most `options.jobs` at a time, in list order. Each child
/// runs in its own process group, so a task past its time limit is killed with everything it
/// started (SIGKILL to the group) and recorded as kTimedOut; one task's crash or kill never stops
/// the others. While the pool runs, SIGINT and SIGTERM to this process kill the running tasks and
/// end the pool: those tasks and the ones not started are kCancelled, and the previous signal
/// dispositions are restored before returning.
/// @throws std::invalid_argument if jobs < 1 or the time limit is negative.
std::vector<ProcessResult> RunProcessPool(const std::vector<ProcessTask>& tasks,
                                          const ProcessPoolOptions& options,
                                          const ProcessDoneCallback& on_done = {});

/// Progress of many tasks on stderr: with `bar`, one line redrawn ("[####....] 3/10 scenes, 0
/// failed, 1m10s elapsed, ETA 2m20s"), else one line per task that ends. Tasks finished before
/// (resumed) count as done; the ETA extrapolates the time per task ended so far.
class ProgressLine {
 public:
  ProgressLine(int total, int resumed, std::string noun, bool bar);
  /// Reports that task `id` ended after `wall_s` [s], as `ok` or failed.
  void Ended(const std::string& id, bool ok, double wall_s);

 private:
  int total_;
  int resumed_;
  int ended_{0};
  int failed_{0};
  std::string noun_;
  bool bar_;
  double start_s_;
};

/// Runs one task and waits for it to end (no time limit, no signal handling).
ProcessResult RunProcess(const ProcessTask& task);

}  // namespace trav::scenarios
