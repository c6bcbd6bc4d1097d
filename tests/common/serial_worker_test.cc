// SerialWorker: jobs done in submission order on a thread of their own, results handed back in
// that order, and what a job throws reaches the taker after the results before it.
#include "common/serial_worker.h"

#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace trav::common {
namespace {

// A worker whose jobs add their number to a running sum, the result of each job.
struct RunningSum {
  long long sum{0};
  std::thread::id worker_id;
  SerialWorker<int, long long> worker{[this](int& job) {
    worker_id = std::this_thread::get_id();
    if (job < 0) throw std::runtime_error("negative job");
    sum += job;
    return sum;
  }};
};

TEST(SerialWorkerTest, DoesTheJobsInOrderOnItsThreadAndHandsTheResultsBackInOrder) {
  RunningSum dut;
  for (int job = 1; job <= 1000; ++job) dut.worker.Submit(job);
  EXPECT_EQ(dut.worker.TakeNext(), 1);
  EXPECT_EQ(dut.worker.TakeNext(), 3);
  std::vector<long long> rest;
  dut.worker.TakeAll(&rest);
  ASSERT_EQ(rest.size(), 998u);
  for (std::size_t i = 0; i < rest.size(); ++i) {
    const long long n = static_cast<long long>(i) + 3;  // the job of rest[i]
    EXPECT_EQ(rest[i], n * (n + 1) / 2);
  }
  // every job is done once TakeAll returns: the worker's state is the submitter's to read
  EXPECT_EQ(dut.sum, 500500);
  EXPECT_NE(dut.worker_id, std::this_thread::get_id());
  // and it goes on after
  dut.worker.Submit(1);
  EXPECT_EQ(dut.worker.TakeNext(), 500501);
}

TEST(SerialWorkerTest, AJobsErrorComesAfterTheResultsBeforeItAndStopsTheWorker) {
  RunningSum dut;
  for (const int job : {1, 2, -1, 4}) dut.worker.Submit(job);
  EXPECT_EQ(dut.worker.TakeNext(), 1);
  EXPECT_EQ(dut.worker.TakeNext(), 3);
  EXPECT_THROW(dut.worker.TakeNext(), std::runtime_error);
  std::vector<long long> results;
  EXPECT_THROW(dut.worker.TakeAll(&results), std::runtime_error);
  EXPECT_TRUE(results.empty());
  EXPECT_EQ(dut.sum, 3);  // job 4 never ran
}

TEST(SerialWorkerTest, TakeAllRethrowsAnErrorWhateverCameBefore) {
  RunningSum dut;
  for (const int job : {5, -1}) dut.worker.Submit(job);
  std::vector<long long> results;
  EXPECT_THROW(dut.worker.TakeAll(&results), std::runtime_error);
  EXPECT_TRUE(results.empty());
}

TEST(SerialWorkerTest, StopsWithJobsStillQueuedAfterAPrefixOfThem) {
  long long sum = 0, done = 0;
  {
    SerialWorker<int, long long> worker([&](int& job) {
      std::this_thread::sleep_for(std::chrono::microseconds(100));
      ++done;
      return sum += job;
    });
    for (int job = 0; job < 1000; ++job) worker.Submit(job);
  }
  // the destructor returned (the job in hand finished, the rest dropped, none half done): the
  // jobs done are the first ones, in order
  EXPECT_EQ(sum, done * (done - 1) / 2);
}

}  // namespace
}  // namespace trav::common
