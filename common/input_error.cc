#include "common/input_error.h"

namespace trav::common {
namespace {

std::string Compose(const std::string& file, const std::string& key_path, const std::string& what) {
  std::string message;
  if (!file.empty()) message += file + ": ";
  if (!key_path.empty()) message += key_path + ": ";
  return message + what;
}

}  // namespace

InputError::InputError(const std::string& message) : std::runtime_error(message) {}

InputError::InputError(const std::string& file, const std::string& key_path,
                       const std::string& what)
    : std::runtime_error(Compose(file, key_path, what)) {}

void RequireValue(bool condition, const std::string& key_path, double value,
                  const std::string& expectation) {
  if (!condition)
    throw InputError("", key_path, "value " + std::to_string(value) + " " + expectation);
}

}  // namespace trav::common
