#pragma once

// Helpers of the tests that run the `trav` command (TRAV_BINARY, defined by each test's CMake).
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <sys/wait.h>

namespace trav::test_util {

/// How a command ended and what it printed.
struct CommandResult {
  int exit_code{-1};   ///< -1 if it did not exit normally
  std::string output;  ///< stdout and stderr
};

/// Runs a shell command, collecting its standard output and error.
inline CommandResult RunCommand(const std::string& command) {
  CommandResult result;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return result;
  char buffer[4096];
  while (std::fgets(buffer, sizeof(buffer), pipe) != nullptr) result.output += buffer;
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

#ifdef TRAV_BINARY
/// Runs `trav` with `arguments` (shell words).
inline CommandResult RunTrav(const std::string& arguments) {
  return RunCommand(std::string(TRAV_BINARY) + " " + arguments);
}
#endif

/// The contents of a file ("" if it cannot be read).
inline std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

/// An empty folder in the temporary directory named after `prefix`, the process and the running
/// test.
inline std::filesystem::path FreshTestFolder(const std::string& prefix) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      (prefix + "_" + std::to_string(getpid()) + "_" +
       ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::filesystem::remove_all(path);
  std::filesystem::create_directories(path);
  return path;
}

}  // namespace trav::test_util
