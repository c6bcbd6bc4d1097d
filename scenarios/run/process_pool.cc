#include "scenarios/run/process_pool.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>
#include <sys/prctl.h>
#include <sys/wait.h>

#include "common/logging.h"

namespace trav::scenarios {
namespace {

using Clock = std::chrono::steady_clock;

// Set by SIGINT or SIGTERM while a pool runs.
volatile std::sig_atomic_t g_interrupted = 0;

void OnInterrupt(int) { g_interrupted = 1; }

// For its lifetime: the interrupt handler, and SIGCHLD blocked so that WaitForChild() wakes when
// a child ends; restores both after.
class PoolSignals {
 public:
  PoolSignals() {
    g_interrupted = 0;
    struct sigaction action {};
    action.sa_handler = OnInterrupt;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &previous_int_);
    sigaction(SIGTERM, &action, &previous_term_);
    sigemptyset(&child_);
    sigaddset(&child_, SIGCHLD);
    pthread_sigmask(SIG_BLOCK, &child_, &previous_mask_);
  }
  ~PoolSignals() {
    pthread_sigmask(SIG_SETMASK, &previous_mask_, nullptr);
    sigaction(SIGINT, &previous_int_, nullptr);
    sigaction(SIGTERM, &previous_term_, nullptr);
  }

  // Sleeps until a child ends, a signal interrupts, or 10 ms pass (the time-limit checks).
  void WaitForChild() const {
    const timespec timeout{0, 10'000'000};
    sigtimedwait(&child_, nullptr, &timeout);
  }
  PoolSignals(const PoolSignals&) = delete;
  PoolSignals& operator=(const PoolSignals&) = delete;

 private:
  struct sigaction previous_int_ {};
  struct sigaction previous_term_ {};
  sigset_t child_{};
  sigset_t previous_mask_{};
};

// A started child.
struct Running {
  std::size_t index;
  pid_t pid;
  Clock::time_point start;
};

// Starts `task` in a process group of its own; returns its pid, or -1 with `result` filled in.
// The child is killed (SIGKILL) when this thread ends, however it ends (PR_SET_PDEATHSIG), so a
// killed batch or evaluation never leaves workers running unsupervised. fork and exec rather than
// posix_spawn, because the parent-death signal must be set in the child.
pid_t Start(const ProcessTask& task, ProcessResult* result) {
  if (task.argv.empty()) {
    result->end = ProcessEnd::kNotStarted;
    result->message = "empty command";
    return -1;
  }
  // everything the child needs, prepared before fork (the child only makes system calls)
  std::vector<std::string> args = task.argv;
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);
  const char* output = task.log_path.empty() ? "/dev/null" : task.log_path.c_str();
  sigset_t mask;
  pthread_sigmask(SIG_SETMASK, nullptr, &mask);
  sigdelset(&mask, SIGCHLD);
  const pid_t parent = getpid();
  int report[2];  // the child writes errno here if it cannot exec; closed by a successful exec
  if (pipe2(report, O_CLOEXEC) != 0) {
    result->end = ProcessEnd::kNotStarted;
    result->message = std::string("cannot start ") + task.argv[0] + ": " + std::strerror(errno);
    return -1;
  }
  const pid_t pid = fork();
  if (pid == 0) {
    close(report[0]);
    int error = 0;
    setpgid(0, 0);
    if (prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || getppid() != parent) _exit(127);
    const int input = open("/dev/null", O_RDONLY);
    const int log = open(output, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (input < 0 || log < 0 || dup2(input, STDIN_FILENO) < 0 || dup2(log, STDOUT_FILENO) < 0 ||
        dup2(log, STDERR_FILENO) < 0) {
      error = errno;
    } else {
      signal(SIGINT, SIG_DFL);
      signal(SIGTERM, SIG_DFL);
      pthread_sigmask(SIG_SETMASK, &mask, nullptr);
      execvp(argv[0], argv.data());
      error = errno;
    }
    const ssize_t written = write(report[1], &error, sizeof(error));
    _exit(written == sizeof(error) ? 127 : 126);
  }
  close(report[1]);
  if (pid < 0) {
    close(report[0]);
    result->end = ProcessEnd::kNotStarted;
    result->message = std::string("cannot start ") + task.argv[0] + ": " + std::strerror(errno);
    return -1;
  }
  setpgid(pid, pid);  // also here, so that the group exists before anyone signals it
  int error = 0;
  ssize_t n = 0;
  while ((n = read(report[0], &error, sizeof(error))) < 0 && errno == EINTR) {
  }
  close(report[0]);
  if (n == sizeof(error)) {
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    result->end = ProcessEnd::kNotStarted;
    result->message = "cannot start " + task.argv[0] + ": " + std::strerror(error);
    return -1;
  }
  return pid;
}

// The result of a child that has ended with wait status `status`.
ProcessResult Ended(int status) {
  ProcessResult result;
  if (WIFEXITED(status)) {
    result.end = ProcessEnd::kExited;
    result.exit_code = WEXITSTATUS(status);
  } else {
    result.end = ProcessEnd::kSignaled;
    result.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  }
  return result;
}

// Kills the child's process group and reaps the child.
void KillAndReap(pid_t pid) {
  kill(-pid, SIGKILL);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
}

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double NowSeconds() {
  return std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
}

std::string Duration(double seconds) {
  const int s = static_cast<int>(std::lround(seconds));
  if (s >= 3600) return fmt::format("{}h{:02}m", s / 3600, (s / 60) % 60);
  return fmt::format("{}m{:02}s", s / 60, s % 60);
}

}  // namespace

ProgressLine::ProgressLine(int total, int resumed, std::string noun, bool bar)
    : total_(total), resumed_(resumed), noun_(std::move(noun)), bar_(bar), start_s_(NowSeconds()) {}

void ProgressLine::Ended(const std::string& id, bool ok, double wall_s) {
  ++ended_;
  if (!ok) ++failed_;
  const double elapsed_s = NowSeconds() - start_s_;
  const int remaining = total_ - resumed_ - ended_;
  const double eta_s = elapsed_s / ended_ * remaining;
  const int done = resumed_ + ended_;
  if (bar_) {
    constexpr int kWidth = 30;
    const int filled = total_ > 0 ? done * kWidth / total_ : kWidth;
    common::LogStatusLine(
        fmt::format("[{}{}] {}/{} {}, {} failed, {} elapsed, ETA {}   ", std::string(filled, '#'),
                    std::string(kWidth - filled, '.'), done, total_, noun_, failed_,
                    Duration(elapsed_s), Duration(eta_s)),
        remaining == 0);
  } else {
    common::Log(common::LogLevel::kInfo,
                fmt::format("{} {} {} in {:.0f} s [{}/{}, ETA {}]", noun_, id,
                            ok ? "finished" : "FAILED", wall_s, done, total_, Duration(eta_s)));
  }
}

std::vector<ProcessResult> RunProcessPool(const std::vector<ProcessTask>& tasks,
                                          const ProcessPoolOptions& options,
                                          const ProcessDoneCallback& on_done) {
  if (options.jobs < 1) throw std::invalid_argument("process pool: jobs must be >= 1");
  if (!(options.time_limit_s >= 0.0)) {
    throw std::invalid_argument("process pool: the time limit must be >= 0");
  }
  std::vector<ProcessResult> results(tasks.size());
  std::vector<bool> finished(tasks.size(), false);
  auto finish = [&](std::size_t index, ProcessResult result) {
    results[index] = std::move(result);
    finished[index] = true;
    if (on_done) on_done(index, results[index]);
  };

  const PoolSignals guard;
  std::vector<Running> running;
  std::size_t next = 0;
  while (next < tasks.size() || !running.empty()) {
    if (g_interrupted) break;
    while (next < tasks.size() && static_cast<int>(running.size()) < options.jobs) {
      ProcessResult not_started;
      const pid_t pid = Start(tasks[next], &not_started);
      if (pid < 0) {
        finish(next, not_started);
      } else {
        running.push_back({next, pid, Clock::now()});
      }
      ++next;
    }
    bool reaped = false;
    for (std::size_t r = 0; r < running.size();) {
      const Running& child = running[r];
      int status = 0;
      const pid_t waited = waitpid(child.pid, &status, WNOHANG);
      const double elapsed_s = SecondsSince(child.start);
      if (waited == child.pid) {
        ProcessResult result = Ended(status);
        result.wall_s = elapsed_s;
        finish(child.index, result);
      } else if (options.time_limit_s > 0.0 && elapsed_s > options.time_limit_s) {
        KillAndReap(child.pid);
        ProcessResult result;
        result.end = ProcessEnd::kTimedOut;
        result.wall_s = elapsed_s;
        finish(child.index, result);
      } else {
        ++r;
        continue;
      }
      running.erase(running.begin() + static_cast<std::ptrdiff_t>(r));
      reaped = true;
    }
    if (!reaped) guard.WaitForChild();
  }

  // interrupted: stop what runs, and mark it and the rest cancelled
  for (const Running& child : running) KillAndReap(child.pid);
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    if (finished[i]) continue;
    ProcessResult cancelled;
    cancelled.end = ProcessEnd::kCancelled;
    results[i] = cancelled;
  }
  return results;
}

ProcessResult RunProcess(const ProcessTask& task) {
  ProcessResult result;
  const Clock::time_point start = Clock::now();
  const pid_t pid = Start(task, &result);
  if (pid < 0) return result;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      result.end = ProcessEnd::kNotStarted;
      result.message = "cannot wait for " + task.argv[0] + ": " + std::strerror(errno);
      return result;
    }
  }
  result = Ended(status);
  result.wall_s = SecondsSince(start);
  return result;
}

}  // namespace trav::scenarios
