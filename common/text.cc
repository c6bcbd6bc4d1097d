#include "common/text.h"

#include <cstdio>

namespace trav::common {

std::string FormatNumber(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

}  // namespace trav::common
