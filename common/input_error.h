#pragma once

#include <stdexcept>
#include <string>

namespace trav::common {

/// Bad input from the user: a malformed scenario, a missing file, an out-of-range value.
/// The `trav` command maps it to exit code 2. The message names the file, the key path and the
/// value.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message);

  /// Builds "<file>: <key_path>: <what>" (parts that are empty are left out).
  InputError(const std::string& file, const std::string& key_path, const std::string& what);
};

/// `text` for an error message: at most `max_length` characters (cut with "..."), bytes outside
/// printable ASCII as \xNN, so that no input can flood or garble a terminal.
std::string Excerpt(const std::string& text, std::size_t max_length = 60);

/// Excerpt() in single quotes.
std::string QuotedExcerpt(const std::string& text, std::size_t max_length = 60);

/// Throws InputError "<key_path>: value <value> <expectation>" unless `condition` holds: the one
/// check every config validator uses (the caller adds the file when it knows it).
void RequireValue(bool condition, const std::string& key_path, double value,
                  const std::string& expectation);

}  // namespace trav::common
