#include "common/helper_thread.h"

namespace trav::common {

HelperThread::HelperThread() : thread_([this] { Work(); }) {}

HelperThread::~HelperThread() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_one();
  thread_.join();
}

void HelperThread::Start(void (*run)(void*), void* job) {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    run_ = run;
    job_ = job;
    error_ = nullptr;
  }
  wake_.notify_one();
}

std::exception_ptr HelperThread::Wait() {
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [this] { return run_ == nullptr; });
  return error_;
}

void HelperThread::Work() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return stop_ || run_ != nullptr; });
    if (stop_) return;
    void (*const run)(void*) = run_;
    void* const job = job_;
    lock.unlock();
    std::exception_ptr error;
    try {
      run(job);
    } catch (...) {
      error = std::current_exception();
    }
    lock.lock();
    error_ = error;
    run_ = nullptr;
    done_.notify_one();
  }
}

}  // namespace trav::common
