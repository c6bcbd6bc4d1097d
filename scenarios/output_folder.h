#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace trav::scenarios {

/// An output folder written atomically: files go into a hidden sibling folder
/// ("<dir>.partial-<pid>") that Commit() renames to the final name, replacing an older folder of
/// that name. If the object is destroyed without Commit() (bad input, a crash unwinding), the
/// partial folder is removed, so no half-written output is ever left under the final name.
class OutputFolder {
 public:
  /// Creates the partial folder (and missing parents). @throws std::runtime_error on failure.
  explicit OutputFolder(const std::string& final_path);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  /// Path of a file inside the partial folder.
  std::string File(const std::string& name) const;

  /// Moves the partial folder to its final name. @throws std::runtime_error on failure.
  void Commit();

  const std::string& final_path() const { return final_path_; }

 private:
  std::string final_path_;
  std::string partial_path_;
  bool committed_{false};
};

/// Writes `text` to `path`. @throws std::runtime_error on failure.
void WriteTextFile(const std::string& path, const std::string& text);

/// The contents of a file, or "" if it cannot be read.
std::string ReadTextFile(const std::string& path);

/// A JSON file. @throws common::InputError naming the file if it cannot be read or parsed.
nlohmann::json ReadJsonFile(const std::string& path);

/// A JSON file, or nothing if it is absent or not valid JSON (a record still to be written).
std::optional<nlohmann::json> ReadJsonIfPresent(const std::string& path);

/// Writes `text` to `path` under a temporary name ("<path>.partial-<pid>") and renames it, so
/// `path` is either complete or as it was. @throws std::runtime_error on failure.
void WriteTextFileAtomically(const std::string& path, const std::string& text);

}  // namespace trav::scenarios
