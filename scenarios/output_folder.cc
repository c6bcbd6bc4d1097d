#include "scenarios/output_folder.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "common/input_error.h"

namespace trav::scenarios {

namespace fs = std::filesystem;

OutputFolder::OutputFolder(const std::string& final_path) {
  fs::path path = fs::path(final_path).lexically_normal();
  if (path.filename().empty()) path = path.parent_path();
  final_path_ = path.string();
  partial_path_ = final_path_ + ".partial-" + std::to_string(getpid());
  std::error_code error;
  fs::remove_all(partial_path_, error);
  fs::create_directories(partial_path_, error);
  if (error) {
    throw std::runtime_error("cannot create output folder " + partial_path_ + ": " +
                             error.message());
  }
}

OutputFolder::~OutputFolder() {
  if (committed_) return;
  std::error_code error;
  fs::remove_all(partial_path_, error);
}

std::string OutputFolder::File(const std::string& name) const {
  return (fs::path(partial_path_) / name).string();
}

void OutputFolder::Commit() {
  std::error_code error;
  const std::string old_path = final_path_ + ".old-" + std::to_string(getpid());
  const bool replacing = fs::exists(final_path_, error);
  if (replacing) {
    fs::rename(final_path_, old_path, error);
    if (error) throw std::runtime_error("cannot replace " + final_path_ + ": " + error.message());
  }
  fs::rename(partial_path_, final_path_, error);
  if (error) throw std::runtime_error("cannot create " + final_path_ + ": " + error.message());
  committed_ = true;
  if (replacing) fs::remove_all(old_path, error);
}

void WriteTextFile(const std::string& path, const std::string& text) {
  std::ofstream file(path, std::ios::binary);
  file << text;
  if (!file) throw std::runtime_error("cannot write " + path);
}

std::string ReadTextFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

nlohmann::json ReadJsonFile(const std::string& path) {
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

void WriteTextFileAtomically(const std::string& path, const std::string& text) {
  const std::string partial = path + ".partial-" + std::to_string(getpid());
  WriteTextFile(partial, text);
  std::error_code error;
  std::filesystem::rename(partial, path, error);
  if (error) {
    std::filesystem::remove(partial, error);
    throw std::runtime_error("cannot write " + path);
  }
}

}  // namespace trav::scenarios
