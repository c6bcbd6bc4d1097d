#pragma once

#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <type_traits>
#include <utility>

namespace trav::common {

/// A persistent thread that runs one job alongside the calling thread's, for work that splits into
/// two independent parts (each reads shared inputs and writes its own outputs): the parts compute
/// what they would on one thread, bit for bit, in less wall time when a core is free. Started once
/// and reused, so a split costs a wake-up, not a thread. Not for concurrent callers.
class HelperThread {
 public:
  HelperThread();
  /// Joins the thread.
  ~HelperThread();
  HelperThread(const HelperThread&) = delete;
  HelperThread& operator=(const HelperThread&) = delete;

  /// Runs `there` on the helper thread and `here` on the calling thread, and returns once both
  /// have; rethrows what either threw (`here`'s first). Allocates nothing.
  template <typename There, typename Here>
  void RunAlongside(There&& there, Here&& here) {
    Start([](void* job) { (*static_cast<std::remove_reference_t<There>*>(job))(); }, &there);
    std::exception_ptr here_error;
    try {
      here();
    } catch (...) {
      here_error = std::current_exception();
    }
    const std::exception_ptr there_error = Wait();
    if (here_error) std::rethrow_exception(here_error);
    if (there_error) std::rethrow_exception(there_error);
  }

 private:
  void Start(void (*run)(void*), void* job);
  std::exception_ptr Wait();
  void Work();

  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;
  void (*run_)(void*){nullptr};  // the job in hand (null: none)
  void* job_{nullptr};
  std::exception_ptr error_;
  bool stop_{false};
  std::thread thread_;  // last: started once the members it reads exist
};

/// Runs `there` and `here` alongside on `helper`, or one after the other when `helper` is null.
template <typename There, typename Here>
void RunAlongside(HelperThread* helper, There&& there, Here&& here) {
  if (helper != nullptr) {
    helper->RunAlongside(std::forward<There>(there), std::forward<Here>(here));
    return;
  }
  there();
  here();
}

}  // namespace trav::common
