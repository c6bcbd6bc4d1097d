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

std::string Excerpt(const std::string& text, std::size_t max_length) {
  std::string quoted;
  std::size_t shown = 0;
  for (const char c : text) {
    if (shown == max_length) {
      quoted += "...";
      break;
    }
    const auto byte = static_cast<unsigned char>(c);
    if (c == '\n' || c == '\t') {
      quoted += ' ';
    } else if (byte >= 0x20 && byte < 0x7f) {
      quoted += c;
    } else {
      static const char kHex[] = "0123456789abcdef";
      quoted += std::string("\\x") + kHex[byte >> 4] + kHex[byte & 0xf];
    }
    ++shown;
  }
  return quoted;
}

std::string QuotedExcerpt(const std::string& text, std::size_t max_length) {
  return "'" + Excerpt(text, max_length) + "'";
}

InputError::InputError(const std::string& message) : std::runtime_error(message), what_(message) {}

InputError::InputError(const std::string& file, const std::string& key_path,
                       const std::string& what)
    : std::runtime_error(Compose(file, key_path, what)),
      file_(file),
      key_path_(key_path),
      what_(what) {}

InputError InputError::AtKey(const std::string& prefix) const {
  if (prefix.empty()) return *this;
  const bool joined_without_dot = key_path_.empty() || key_path_.front() == '[';
  const std::string key = joined_without_dot ? prefix + key_path_ : prefix + "." + key_path_;
  return InputError(file_, key, what_);
}

InputError InputError::InFile(const std::string& file) const {
  if (!file_.empty()) return *this;
  return InputError(file, key_path_, what_);
}

void RequireValue(bool condition, const std::string& key_path, double value,
                  const std::string& expectation) {
  if (!condition)
    throw InputError("", key_path, "value " + std::to_string(value) + " " + expectation);
}

}  // namespace trav::common
