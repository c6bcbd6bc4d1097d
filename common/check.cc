#include "common/check.h"

namespace trav::common {

void FailDemand(const char* condition, const char* file, int line) {
  throw PreconditionError(std::string(file) + ":" + std::to_string(line) + ": " + condition +
                          " does not hold");
}

}  // namespace trav::common
