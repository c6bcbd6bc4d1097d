#pragma once

#include <time.h>

#include <chrono>

namespace trav::common {

/// Wall time since construction or the last Restart (the steady clock). For the timings a run
/// reports; never for a decision inside a run (those use iteration caps and simulation time).
class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}

  void Restart() { start_ = std::chrono::steady_clock::now(); }

  double ElapsedSeconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

  double ElapsedMilliseconds() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_)
        .count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

/// CPU time of the calling thread since construction (CLOCK_THREAD_CPUTIME_ID): what a
/// computation costs whatever else loads the machine, where wall time on a shared machine reads
/// several times more.
class ThreadCpuStopwatch {
 public:
  ThreadCpuStopwatch() : start_s_(Now()) {}

  double ElapsedMilliseconds() const { return 1e3 * (Now() - start_s_); }

 private:
  static double Now() {
    timespec now{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
    return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
  }
  double start_s_;
};

}  // namespace trav::common
