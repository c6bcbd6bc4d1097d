#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace trav::scenarios {

/// The marker file trav writes into every folder it creates as a result ("<folder>/.trav", JSON
/// {"kind": ...}); a folder without it is never replaced, deleted or written into by trav.
inline constexpr const char* kFolderMarker = ".trav";

/// The kind recorded in a folder's marker ("run", "terrain", "batch", "eval", "tune"), or nothing
/// if the folder has no readable marker.
std::optional<std::string> FolderKindOf(const std::string& folder);

/// An output folder written atomically: files go into a hidden sibling folder
/// ("<dir>.partial-<pid>", marked with `kind`) that Commit() renames to the final name. If the
/// object is destroyed without Commit() (bad input, an error unwinding), the partial folder and
/// the parent folders it created are removed, so nothing half-written is left.
///
/// It never loses data: the final path must not exist, or be an empty folder, or, with
/// `overwrite`, a writable folder whose marker has the same `kind` (an earlier result of the same
/// command), which Commit() replaces. Anything else (a file, a folder of the user's, a read-only
/// result, a result of another kind) is bad input, checked when the object is made and again at
/// Commit(). Partial folders that killed trav processes left beside the final path are removed.
class OutputFolder {
 public:
  /// @throws common::InputError naming the path if it may not be written; std::runtime_error if
  /// the partial folder cannot be created.
  OutputFolder(const std::string& final_path, const std::string& kind, bool overwrite);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  /// Path of a file inside the partial folder.
  std::string File(const std::string& name) const;

  /// Moves the partial folder to its final name. @throws common::InputError if the final path
  /// has meanwhile become something trav may not replace, or cannot be renamed.
  void Commit();

  const std::string& final_path() const { return final_path_; }

 private:
  std::string final_path_;
  std::string partial_path_;
  std::string kind_;
  bool overwrite_;
  std::vector<std::string> created_parents_;  ///< deepest first
  bool committed_{false};
};

/// A folder that many processes fill over time (a batch, an evaluation, a tuning), opened for
/// one trav process at a time: created if absent (marked with `kind`), else accepted if it is
/// empty, holds the marker of `kind`, or holds `identity_file` (written by trav before markers
/// existed). Anything else is bad input. The folder is locked (flock on "<folder>/.trav.lock")
/// for the object's lifetime, so two trav processes never work in one folder at once; the lock
/// goes with the process, however it ends. Files a killed process left half-written
/// ("*.partial-*") in the folder itself and in `partial_subfolders` are removed.
class CampaignFolder {
 public:
  /// What the folder may be when it is opened.
  enum class Use {
    kCreateOrResume,  ///< new, empty, or one of `kind` (run or resume a campaign)
    kExisting,        ///< one of `kind` only (collect its results)
  };

  /// @throws common::InputError naming the folder if it may not be used or is in use.
  CampaignFolder(const std::string& path, const std::string& kind, const std::string& identity_file,
                 const std::vector<std::string>& partial_subfolders,
                 Use use = Use::kCreateOrResume);
  ~CampaignFolder();
  CampaignFolder(const CampaignFolder&) = delete;
  CampaignFolder& operator=(const CampaignFolder&) = delete;

  /// The folder's absolute path.
  const std::string& path() const { return path_; }

  /// Claims the folder for one campaign, `identity` being what decides its results (the runs,
  /// the options): a folder without an identity file gets one (written atomically); one whose
  /// identity file `is_same` rejects holds another campaign and is refused with `refusal`.
  /// @throws common::InputError naming the identity file.
  void Claim(const nlohmann::json& identity,
             const std::function<bool(const nlohmann::json& previous)>& is_same,
             const std::string& refusal) const;

 private:
  std::string path_;
  std::string identity_file_;
  int lock_fd_{-1};
};

/// A name that is safe as one path component: letters, digits, '_', '-' and '.' kept, anything
/// else '-', a leading '.' as '_', empty as "_", and longer than 96 characters cut with a hash of
/// the whole appended, so that no name can be "." or "..", hold a '/', or be too long.
std::string SafeFileName(const std::string& text);

/// Writes `text` to `path` and checks every step through fsync and close.
/// @throws common::InputError naming the file and the system's reason (a full disk, no
/// permission).
void WriteTextFile(const std::string& path, const std::string& text);

/// The contents of a file, or "" if it cannot be read.
std::string ReadTextFile(const std::string& path);

/// A JSON file. @throws common::InputError naming the file if it cannot be read or parsed.
nlohmann::json ReadJsonFile(const std::string& path);

/// A JSON file, or nothing if it is absent or not valid JSON (a record still to be written).
std::optional<nlohmann::json> ReadJsonIfPresent(const std::string& path);

/// Writes `text` to `path` under a temporary name ("<path>.partial-<pid>"), checked through
/// fsync and close (WriteTextFile), then renames it, so `path` is either complete or as it was.
/// @throws common::InputError naming the file on failure (the temporary file is removed).
void WriteTextFileAtomically(const std::string& path, const std::string& text);

/// Writes a file through `write(partial_path)` under the temporary name "<path>.partial-<pid>" and
/// renames it to `path` once `write` has returned: `path` holds a complete file or none; the
/// partial file is removed if `write` throws (the exception passes on) or the rename fails.
/// @throws common::InputError naming `path` if the rename fails.
void WriteFileAtomically(const std::string& path,
                         const std::function<void(const std::string&)>& write);

/// Checks a stream that wrote `path` after closing it. @throws common::InputError naming the file
/// (with the system's reason) if any write failed.
void CheckWritten(const std::string& path, bool stream_ok);

}  // namespace trav::scenarios
