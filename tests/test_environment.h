#pragma once

#include <cstdlib>
#include <cstring>

// Whether the tests run in CI (CI=true, as CI services set it): there a missing dependency that a
// test would skip for on a developer's machine is a failure, since scripts/install-deps installs
// everything.
inline bool RunningInCi() {
  const char* ci = std::getenv("CI");
  return ci != nullptr && std::strcmp(ci, "true") == 0;
}

// Skips the test with `reason`, or fails it under CI.
#define TRAV_SKIP_UNLESS_CI(reason)                                                    \
  do {                                                                                 \
    if (RunningInCi()) FAIL() << reason << " (CI=true: every dependency is required)"; \
    GTEST_SKIP() << reason;                                                            \
  } while (false)
