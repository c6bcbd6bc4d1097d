#include "scenarios/run/output_folder.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include <fmt/format.h>
#include <sys/file.h>

#include "common/input_error.h"

namespace trav::scenarios {

namespace fs = std::filesystem;

namespace {

// The system's reason for the last failed call.
std::string Reason() { return std::strerror(errno); }

void WriteMarker(const fs::path& folder, const std::string& kind) {
  WriteTextFile((folder / kFolderMarker).string(), nlohmann::json{{"kind", kind}}.dump() + "\n");
}

bool IsEmptyFolder(const fs::path& path) {
  std::error_code error;
  return fs::is_directory(path, error) && fs::is_empty(path, error) && !error;
}

// Throws InputError unless `path` is free of control characters (which no tool downstream, from
// a shell to gnuplot, reads safely).
void RequirePrintablePath(const std::string& path) {
  for (const char c : path) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) {
      throw common::InputError(common::QuotedExcerpt(path, 200), "",
                               "an output folder name must not hold control characters");
    }
  }
}

// Why trav may not put a result of `kind` at `path` (empty: it may).
std::string RefusalReason(const fs::path& path, const std::string& kind, bool overwrite) {
  std::error_code error;
  const fs::file_status status = fs::symlink_status(path, error);
  if (!fs::exists(status)) return "";
  if (!fs::is_directory(status)) return "exists and is not a folder; trav does not replace it";
  if (IsEmptyFolder(path)) return "";
  const std::optional<std::string> found = FolderKindOf(path.string());
  if (!found) {
    return "exists and is not a trav result; trav never replaces a folder it did not write "
           "(choose another output folder)";
  }
  if (*found != kind) {
    return "holds a trav " + *found + " result, not a " + kind + " result; choose another output " +
           "folder";
  }
  if (!overwrite) {
    return "holds an earlier " + kind + " result; pass --overwrite to replace it, or choose " +
           "another output folder";
  }
  // the owner's write bit, not access(): a folder made read-only is protected from root too
  if ((fs::status(path, error).permissions() & fs::perms::owner_write) == fs::perms::none ||
      access(path.c_str(), W_OK) != 0) {
    return "is read-only; trav does not replace it";
  }
  return "";
}

// Whether process `pid` may still be running (an unknown answer counts as running).
bool MayBeRunning(long pid) {
  if (pid <= 0) return true;
  return kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH;
}

// Removes "<name>.partial-<pid>" siblings of `path` whose process has ended and which carry
// trav's marker (a killed trav's leftovers; nothing of anyone else's).
void RemoveStalePartials(const fs::path& path) {
  const std::string prefix = path.filename().string() + ".partial-";
  std::error_code error;
  fs::directory_iterator entries(path.parent_path().empty() ? "." : path.parent_path(), error);
  if (error) return;
  for (const fs::directory_entry& entry : entries) {
    const std::string name = entry.path().filename().string();
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string pid_text = name.substr(prefix.size());
    if (pid_text.empty() || pid_text.find_first_not_of("0123456789") != std::string::npos ||
        pid_text.size() > 9) {
      continue;
    }
    if (MayBeRunning(std::stol(pid_text))) continue;
    if (!FolderKindOf(entry.path().string())) continue;
    fs::remove_all(entry.path(), error);
  }
}

}  // namespace

std::optional<std::string> FolderKindOf(const std::string& folder) {
  const std::optional<nlohmann::json> marker =
      ReadJsonIfPresent((fs::path(folder) / kFolderMarker).string());
  if (!marker || !marker->is_object() || !marker->contains("kind") ||
      !(*marker)["kind"].is_string()) {
    return std::nullopt;
  }
  return (*marker)["kind"].get<std::string>();
}

OutputFolder::OutputFolder(const std::string& final_path, const std::string& kind, bool overwrite)
    : kind_(kind), overwrite_(overwrite) {
  if (final_path.empty()) throw common::InputError("--out", "", "the output folder is empty");
  RequirePrintablePath(final_path);
  fs::path path = fs::absolute(fs::path(final_path)).lexically_normal();
  if (path.filename().empty()) path = path.parent_path();
  if (path == path.root_path()) {
    throw common::InputError(final_path, "", "the root folder cannot be an output folder");
  }
  final_path_ = path.string();
  const std::string refusal = RefusalReason(path, kind_, overwrite_);
  if (!refusal.empty()) throw common::InputError(final_path, "", refusal);

  // the parents that do not exist yet, to remove again if nothing is committed
  for (fs::path parent = path.parent_path(); !parent.empty() && parent != parent.root_path();
       parent = parent.parent_path()) {
    std::error_code error;
    if (fs::exists(fs::symlink_status(parent, error))) break;
    created_parents_.push_back(parent.string());
  }
  std::error_code error;
  fs::create_directories(path.parent_path(), error);
  if (error) {
    throw common::InputError(final_path, "", "cannot create its parent folder: " + error.message());
  }
  RemoveStalePartials(path);
  partial_path_ = final_path_ + ".partial-" + std::to_string(getpid());
  fs::remove_all(partial_path_, error);
  fs::create_directory(partial_path_, error);
  if (error) {
    const std::string message = error.message();
    for (const std::string& parent : created_parents_) fs::remove(parent, error);
    throw common::InputError(final_path, "", "cannot create the output folder: " + message);
  }
  WriteMarker(partial_path_, kind_);
}

OutputFolder::~OutputFolder() {
  if (committed_) return;
  std::error_code error;
  fs::remove_all(partial_path_, error);
  // only folders that are still empty: another process may have put something there meanwhile
  for (const std::string& parent : created_parents_) fs::remove(parent, error);
}

std::string OutputFolder::File(const std::string& name) const {
  return (fs::path(partial_path_) / name).string();
}

void OutputFolder::Commit() {
  const std::string refusal = RefusalReason(final_path_, kind_, overwrite_);
  if (!refusal.empty()) throw common::InputError(final_path_, "", refusal);
  std::error_code error;
  const bool replacing = fs::exists(final_path_, error) && !IsEmptyFolder(final_path_);
  const std::string old_path = final_path_ + ".old-" + std::to_string(getpid());
  if (replacing) {
    fs::rename(final_path_, old_path, error);
    if (error) throw common::InputError(final_path_, "", "cannot replace: " + error.message());
  }
  // rename(2) also replaces an empty folder
  fs::rename(partial_path_, final_path_, error);
  if (error) {
    const std::string message = error.message();
    if (replacing) fs::rename(old_path, final_path_, error);
    throw common::InputError(final_path_, "", "cannot create: " + message);
  }
  committed_ = true;
  if (replacing) fs::remove_all(old_path, error);
}

CampaignFolder::CampaignFolder(const std::string& path, const std::string& kind,
                               const std::string& identity_file,
                               const std::vector<std::string>& partial_subfolders, Use use)
    : identity_file_(identity_file) {
  if (path.empty()) throw common::InputError("--out", "", "the output folder is empty");
  RequirePrintablePath(path);
  const fs::path folder = fs::absolute(fs::path(path)).lexically_normal();
  path_ = folder.string();
  if (!path_.empty() && path_.back() == '/' && path_.size() > 1) path_.pop_back();
  std::error_code error;
  const fs::file_status status = fs::symlink_status(folder, error);
  bool fresh = !fs::exists(status);
  if (use == Use::kExisting &&
      (fresh || (!FolderKindOf(path_) && !fs::is_regular_file(folder / identity_file, error)))) {
    throw common::InputError(path, "", "holds no trav " + kind + " (no " + identity_file + ")");
  }
  if (!fresh) {
    if (!fs::is_directory(status)) {
      throw common::InputError(path, "", "exists and is not a folder; trav does not replace it");
    }
    const std::optional<std::string> found = FolderKindOf(path_);
    const bool legacy = !found && fs::is_regular_file(folder / identity_file, error);
    if (found && *found != kind) {
      throw common::InputError(
          path, "",
          "holds a trav " + *found + ", not a " + kind + "; choose another output folder");
    }
    if (!found && !legacy && !IsEmptyFolder(folder)) {
      throw common::InputError(path, "",
                               "exists and is not a trav " + kind + " folder; trav writes a " +
                                   kind + " only into a new or empty folder, or resumes its own");
    }
    fresh = !found;
  }
  fs::create_directories(folder, error);
  if (error) throw common::InputError(path, "", "cannot create the folder: " + error.message());
  const std::string lock_path = (folder / ".trav.lock").string();
  lock_fd_ = open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0) throw common::InputError(path, "", "cannot open its lock file: " + Reason());
  if (flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    const std::string holder = ReadTextFile(lock_path);
    close(lock_fd_);
    lock_fd_ = -1;
    throw common::InputError(path, "",
                             "is in use by another trav process" +
                                 (holder.empty() ? std::string() : " (pid " + holder + ")") +
                                 "; wait for it to end, or choose another output folder");
  }
  // the holder's pid, for the message a second process prints (the lock holds without it)
  const std::string pid = std::to_string(getpid());
  const bool noted = ftruncate(lock_fd_, 0) == 0 && write(lock_fd_, pid.data(), pid.size()) > 0;
  static_cast<void>(noted);
  if (fresh) WriteMarker(folder, kind);
  // the folder itself (a report killed while written) and the subfolders the campaign names
  std::vector<std::string> swept = partial_subfolders;
  swept.emplace_back();
  for (const std::string& sub : swept) {
    fs::directory_iterator entries(sub.empty() ? folder : folder / sub, error);
    if (error) continue;
    for (const fs::directory_entry& entry : entries) {
      if (entry.path().filename().string().find(".partial-") != std::string::npos) {
        fs::remove_all(entry.path(), error);
      }
    }
  }
}

void CampaignFolder::Claim(const nlohmann::json& identity,
                           const std::function<bool(const nlohmann::json& previous)>& is_same,
                           const std::string& refusal) const {
  const std::string identity_path = (fs::path(path_) / identity_file_).string();
  std::error_code error;
  if (!fs::exists(identity_path, error)) {
    WriteTextFileAtomically(identity_path, identity.dump(1) + "\n");
  } else if (!is_same(ReadJsonFile(identity_path))) {
    throw common::InputError(identity_path, "", refusal);
  }
}

CampaignFolder::~CampaignFolder() {
  if (lock_fd_ >= 0) close(lock_fd_);
}

std::string SafeFileName(const std::string& text) {
  constexpr std::size_t kMaxLength = 96;
  std::string out = text.empty() ? "_" : text;
  for (char& c : out) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                       c == '.' || c == '_' || c == '-';
    if (!plain) c = '-';
  }
  if (out.front() == '.') out.front() = '_';
  if (out.size() > kMaxLength) {
    std::uint64_t hash = 1469598103934665603ull;  // FNV-1a of the whole text
    for (const char c : text) hash = (hash ^ static_cast<unsigned char>(c)) * 1099511628211ull;
    out = fmt::format("{}-{:016x}", out.substr(0, kMaxLength - 17), hash);
  }
  return out;
}

void WriteTextFile(const std::string& path, const std::string& text) {
  const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw common::InputError(path, "", "cannot write: " + Reason());
  std::size_t written = 0;
  while (written < text.size()) {
    const ssize_t n = write(fd, text.data() + written, text.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string reason = n < 0 ? Reason() : "nothing written";
      close(fd);
      throw common::InputError(path, "", "cannot write: " + reason);
    }
    written += static_cast<std::size_t>(n);
  }
  if (fsync(fd) != 0 && errno != EINVAL) {
    const std::string reason = Reason();
    close(fd);
    throw common::InputError(path, "", "cannot write: " + reason);
  }
  if (close(fd) != 0) throw common::InputError(path, "", "cannot write: " + Reason());
}

void CheckWritten(const std::string& path, bool stream_ok) {
  if (stream_ok) return;
  const std::string reason = errno != 0 ? Reason() : "write failed";
  throw common::InputError(path, "", "cannot write: " + reason);
}

std::string ReadTextFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

nlohmann::json ReadJsonFile(const std::string& path) {
  std::error_code error;
  if (!fs::is_regular_file(path, error)) throw common::InputError(path, "", "cannot read");
  std::ifstream file(path);
  if (!file) throw common::InputError(path, "", "cannot read");
  nlohmann::json json = nlohmann::json::parse(file, nullptr, false);
  if (json.is_discarded()) throw common::InputError(path, "", "is not valid JSON");
  return json;
}

std::optional<nlohmann::json> ReadJsonIfPresent(const std::string& path) {
  std::error_code error;
  if (!fs::is_regular_file(path, error)) return std::nullopt;
  std::ifstream file(path);
  nlohmann::json json = nlohmann::json::parse(file, nullptr, false);
  if (json.is_discarded()) return std::nullopt;
  return json;
}

void WriteFileAtomically(const std::string& path,
                         const std::function<void(const std::string&)>& write) {
  const std::string partial = path + ".partial-" + std::to_string(getpid());
  std::error_code error;
  try {
    write(partial);
  } catch (...) {
    fs::remove(partial, error);
    throw;
  }
  fs::rename(partial, path, error);
  if (error) {
    const std::string message = error.message();
    fs::remove(partial, error);
    throw common::InputError(path, "", "cannot write: " + message);
  }
}

void WriteTextFileAtomically(const std::string& path, const std::string& text) {
  WriteFileAtomically(path, [&text](const std::string& partial) { WriteTextFile(partial, text); });
}

}  // namespace trav::scenarios
