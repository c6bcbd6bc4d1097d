#include "common/logging.h"

#include <atomic>
#include <cstdio>
#include <mutex>

namespace trav::common {
namespace {

// The logger is the one piece of process-wide state: the level and the lock that keeps lines whole.
std::atomic<int> g_level{static_cast<int>(LogLevel::kInfo)};
std::mutex g_write_mutex;

const char* LevelName(LogLevel level) {
  switch (level) {
    case LogLevel::kDebug:
      return "debug";
    case LogLevel::kInfo:
      return "info";
    case LogLevel::kWarning:
      return "warning";
    case LogLevel::kError:
      return "error";
  }
  return "?";
}

}  // namespace

void SetLogLevel(LogLevel level) { g_level = static_cast<int>(level); }

void Log(LogLevel level, const std::string& message) {
  if (static_cast<int>(level) < g_level) return;
  std::lock_guard<std::mutex> lock(g_write_mutex);
  std::fprintf(stderr, "[trav %s] %s\n", LevelName(level), message.c_str());
}

void LogStatusLine(const std::string& text, bool final) {
  if (static_cast<int>(LogLevel::kInfo) < g_level) return;
  std::lock_guard<std::mutex> lock(g_write_mutex);
  std::fprintf(stderr, "\r%s%s", text.c_str(), final ? "\n" : "");
}

}  // namespace trav::common
