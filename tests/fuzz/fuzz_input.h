#pragma once
// What every fuzz target shares: the input as a file, and the rule that bad input may only end as
// a rejection trav reports with exit 2 (the exceptions main maps to it); anything else (another
// exception, a crash, a leak, a hang) is a bug the fuzzer reports.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "common/input_error.h"

namespace trav::fuzz {

/// A folder of its own for one fuzz process, removed at exit.
inline const std::filesystem::path& ScratchFolder() {
  static const std::filesystem::path folder = [] {
    const std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("trav-fuzz-" + std::to_string(getpid()));
    std::filesystem::create_directories(path);
    std::atexit([] {
      std::error_code error;
      std::filesystem::remove_all(
          std::filesystem::temp_directory_path() / ("trav-fuzz-" + std::to_string(getpid())),
          error);
    });
    return path;
  }();
  return folder;
}

/// Writes the input to `name` in the scratch folder and returns its path.
inline std::string InputFile(const std::uint8_t* data, std::size_t size, const std::string& name) {
  const std::string path = (ScratchFolder() / name).string();
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

/// Runs `work`; returns normally if it succeeds or rejects its input as trav's main does (exit 2).
template <typename Work>
void ExpectCleanRejection(Work work) {
  try {
    work();
  } catch (const common::InputError&) {
  } catch (const std::filesystem::filesystem_error&) {
  } catch (const nlohmann::json::exception&) {
  }
}

}  // namespace trav::fuzz
