#pragma once

#include <stdexcept>
#include <string>

namespace trav::common {

/// Bad input from the user: a malformed scenario, a missing file, an out-of-range value.
/// The `trav` command maps it to exit code 2. The message names the file, the key path and the
/// value.
///
/// A config validator names keys relative to its own struct ("rate"); whoever knows where the
/// struct sits in a file adds the rest with AtKey ("lidar" -> "lidar.rate") and InFile, so no
/// algorithm module knows the scenario's layout.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message);

  /// Builds "<file>: <key_path>: <what>" (parts that are empty are left out).
  InputError(const std::string& file, const std::string& key_path, const std::string& what);

  /// The file named, or empty.
  const std::string& file() const { return file_; }

  /// The key path named, or empty.
  const std::string& key_path() const { return key_path_; }

  /// The same error with `prefix` in front of its key path: "lidar" and "rate" give "lidar.rate",
  /// "moving_obstacles" and "[2].name" give "moving_obstacles[2].name".
  InputError AtKey(const std::string& prefix) const;

  /// The same error in `file`, unless it names a file already (a file the input refers to).
  InputError InFile(const std::string& file) const;

 private:
  std::string file_;
  std::string key_path_;
  std::string what_;
};

/// Runs `validate`, adding `key_prefix` to the key path of any InputError it throws.
template <typename Validate>
void ValidateAt(const std::string& key_prefix, Validate&& validate) {
  try {
    validate();
  } catch (const InputError& e) {
    throw e.AtKey(key_prefix);
  }
}

/// `text` for an error message: at most `max_length` characters (cut with "..."), bytes outside
/// printable ASCII as \xNN, so that no input can flood or garble a terminal.
std::string Excerpt(const std::string& text, std::size_t max_length = 60);

/// Excerpt() in single quotes.
std::string QuotedExcerpt(const std::string& text, std::size_t max_length = 60);

/// Throws InputError "<key_path>: value <value> <expectation>" unless `condition` holds: the one
/// check every config validator uses, with a key relative to the validated struct.
void RequireValue(bool condition, const std::string& key_path, double value,
                  const std::string& expectation);

}  // namespace trav::common
