#pragma once

#include <sstream>
#include <string>

namespace trav::common {

/// Severity of a log line.
enum class LogLevel { kDebug = 0, kInfo = 1, kWarning = 2, kError = 3 };

/// Sets the lowest level that is written (default kInfo). Lines go to stderr.
void SetLogLevel(LogLevel level);

/// Writes one line "[trav level] message" to stderr if `level` is enabled. Thread-safe.
void Log(LogLevel level, const std::string& message);

/// Writes a status line that redraws itself on a terminal ("\r" + text, then a newline when
/// `final`), at level info; for progress bars. Thread-safe.
void LogStatusLine(const std::string& text, bool final);

/// Streams its arguments into one log line: `LogStream(LogLevel::kInfo) << "x = " << x;`.
class LogStream {
 public:
  explicit LogStream(LogLevel level) : level_(level) {}
  LogStream(const LogStream&) = delete;
  LogStream& operator=(const LogStream&) = delete;
  ~LogStream() { Log(level_, stream_.str()); }

  template <typename T>
  LogStream& operator<<(const T& value) {
    stream_ << value;
    return *this;
  }

 private:
  LogLevel level_;
  std::ostringstream stream_;
};

}  // namespace trav::common
