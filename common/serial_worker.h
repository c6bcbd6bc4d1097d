#pragma once

#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace trav::common {

/// A thread of its own that does submitted jobs one at a time, in the order submitted, while the
/// submitter goes on, and keeps their results in that order until taken. What a job computes
/// does not depend on when it runs: the jobs see the work function's state in submission order,
/// as on the submitter's thread. The work function is the worker's alone from construction to
/// destruction, except while the worker is idle (after TakeAll). Not for concurrent submitters.
template <typename Job, typename Result>
class SerialWorker {
 public:
  /// Starts the thread that calls `work` on each job.
  explicit SerialWorker(std::function<Result(Job&)> work)
      : work_(std::move(work)), thread_([this] { Work(); }) {}

  /// Stops the thread; jobs not yet started are dropped.
  ~SerialWorker() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    job_ready_.notify_one();
    thread_.join();
  }
  SerialWorker(const SerialWorker&) = delete;
  SerialWorker& operator=(const SerialWorker&) = delete;

  /// Queues `job` behind those submitted before it.
  void Submit(Job job) {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      inbox_.push_back(std::move(job));
    }
    job_ready_.notify_one();
  }

  /// Waits for the result of the oldest job whose result has not been taken, and returns it.
  /// Rethrows what a job threw once the results before it are taken (the worker stops there).
  Result TakeNext() {
    std::unique_lock<std::mutex> lock(mutex_);
    result_ready_.wait(lock, [this] { return !results_.empty() || error_ != nullptr; });
    if (results_.empty()) std::rethrow_exception(error_);
    Result result = std::move(results_.front());
    results_.pop_front();
    return result;
  }

  /// Waits until every job submitted is done, then appends the results not yet taken, in order.
  /// Rethrows what a job threw (the worker stops there).
  void TakeAll(std::vector<Result>* results) {
    std::unique_lock<std::mutex> lock(mutex_);
    result_ready_.wait(lock, [this] { return (inbox_.empty() && !busy_) || error_ != nullptr; });
    if (error_ != nullptr) std::rethrow_exception(error_);
    for (Result& result : results_) results->push_back(std::move(result));
    results_.clear();
  }

 private:
  void Work() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      job_ready_.wait(lock, [this] { return stop_ || !inbox_.empty(); });
      if (stop_) return;
      Job job = std::move(inbox_.front());
      inbox_.pop_front();
      busy_ = true;
      lock.unlock();
      try {
        Result result = work_(job);
        lock.lock();
        results_.push_back(std::move(result));
      } catch (...) {
        lock.lock();
        error_ = std::current_exception();
        stop_ = true;
      }
      busy_ = false;
      result_ready_.notify_one();
    }
  }

  std::function<Result(Job&)> work_;
  std::mutex mutex_;
  std::condition_variable job_ready_;
  std::condition_variable result_ready_;
  std::deque<Job> inbox_;
  std::deque<Result> results_;
  std::exception_ptr error_;
  bool busy_{false};
  bool stop_{false};
  std::thread thread_;  // last: started once the members it reads exist
};

}  // namespace trav::common
