#pragma once
// Minimal thread-safe logging to stderr: "2026-11-21T22:40:01.123Z INFO  tracker: text".

#include <chrono>
#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>

namespace stereoball::log {

enum class Level { kDebug = 0, kInfo = 1, kWarn = 2, kError = 3 };

/// Sets the component name printed on every line and the minimum level.
void init(std::string_view component, Level min_level = Level::kInfo);
/// Parses "debug|info|warn|error"; nullopt-like false on bad input.
bool parse_level(std::string_view text, Level& out);
void write(Level level, std::string_view text);
/// One log line (no newline): ISO 8601 UTC time with milliseconds, level, component, text.
std::string format_line(Level level, std::string_view component, std::string_view text,
                        std::chrono::system_clock::time_point when);

template <typename... Args>
std::string concat(const Args&... args) {
  std::ostringstream os;
  (os << ... << args);
  return os.str();
}

template <typename... Args>
void debug(const Args&... args) {
  write(Level::kDebug, concat(args...));
}
template <typename... Args>
void info(const Args&... args) {
  write(Level::kInfo, concat(args...));
}
template <typename... Args>
void warn(const Args&... args) {
  write(Level::kWarn, concat(args...));
}
template <typename... Args>
void error(const Args&... args) {
  write(Level::kError, concat(args...));
}

/// Lets a message through at most once per period; counts what it suppressed.
class Throttle {
 public:
  explicit Throttle(int64_t period_ns) : period_ns_(period_ns) {}
  /// True if a message may be logged at now_ns; suppressed() tells how many were held back.
  bool allow(int64_t now_ns);
  uint64_t suppressed() const { return suppressed_; }

 private:
  int64_t period_ns_;
  int64_t last_ns_ = INT64_MIN;
  uint64_t suppressed_ = 0;
};

}  // namespace stereoball::log
