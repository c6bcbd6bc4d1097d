#include "common/text.h"

#include <fmt/printf.h>

namespace trav::common {

std::string FormatNumber(const char* format, double value) { return fmt::sprintf(format, value); }

}  // namespace trav::common
