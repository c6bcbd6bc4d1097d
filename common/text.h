#pragma once

#include <string>

namespace trav::common {

/// One number formatted by a printf conversion for a double (for example "%.6g"), as reports and
/// CSV files write it.
std::string FormatNumber(const char* format, double value);

}  // namespace trav::common
