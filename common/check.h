#pragma once

#include <stdexcept>
#include <string>

namespace trav::common {

/// The error of a broken precondition: a programming error, never bad input (trav exits 3).
class PreconditionError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

/// Throws PreconditionError "<file>:<line>: <condition> does not hold".
[[noreturn]] void FailDemand(const char* condition, const char* file, int line);

}  // namespace trav::common

/// Always-on check of a documented precondition (kept in release builds, unlike assert): throws
/// common::PreconditionError naming the condition and where it was demanded.
#define TRAV_DEMAND(condition)                                                    \
  do {                                                                            \
    if (!(condition)) ::trav::common::FailDemand(#condition, __FILE__, __LINE__); \
  } while (false)
