// HelperThread: both parts run, each exactly once per call, and what either throws reaches the
// caller; the thread is reused from call to call.
#include "common/helper_thread.h"

#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace trav::common {
namespace {

TEST(HelperThreadTest, RunsBothPartsTheThereOneOnTheHelper) {
  HelperThread helper;
  std::vector<int> halves(2, 0);
  std::thread::id there_id, here_id;
  for (int call = 0; call < 1000; ++call) {
    helper.RunAlongside(
        [&] {
          ++halves[0];
          there_id = std::this_thread::get_id();
        },
        [&] {
          ++halves[1];
          here_id = std::this_thread::get_id();
        });
  }
  EXPECT_EQ(halves, (std::vector<int>{1000, 1000}));
  EXPECT_EQ(here_id, std::this_thread::get_id());
  EXPECT_NE(there_id, here_id);
}

TEST(HelperThreadTest, WithoutAHelperBothPartsRunHereInOrder) {
  std::vector<int> order;
  RunAlongside(
      nullptr, [&] { order.push_back(1); }, [&] { order.push_back(2); });
  EXPECT_EQ(order, (std::vector<int>{1, 2}));
}

TEST(HelperThreadTest, WhatEitherPartThrowsReachesTheCallerAndTheHelperGoesOn) {
  HelperThread helper;
  int here_runs = 0;
  EXPECT_THROW(helper.RunAlongside([] { throw std::runtime_error("there"); }, [&] { ++here_runs; }),
               std::runtime_error);
  EXPECT_EQ(here_runs, 1);  // the caller's part ran in full
  int there_runs = 0;
  try {
    helper.RunAlongside([&] { ++there_runs; }, [] { throw std::logic_error("here"); });
    FAIL() << "nothing thrown";
  } catch (const std::logic_error& error) {
    EXPECT_STREQ(error.what(), "here");
  }
  EXPECT_EQ(there_runs, 1);  // waited for before the rethrow
  // the helper still works, and an earlier error does not come back
  helper.RunAlongside([&] { ++there_runs; }, [&] { ++here_runs; });
  EXPECT_EQ(there_runs, 2);
  EXPECT_EQ(here_runs, 2);
}

}  // namespace
}  // namespace trav::common
