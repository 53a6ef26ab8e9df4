#include "common/util/log.hpp"

#include <chrono>
#include <cstdio>
#include <ctime>
#include <mutex>

namespace stereoball::log {
namespace {
std::mutex g_mutex;
std::string g_component = "stereoball";
Level g_min_level = Level::kInfo;

const char* level_name(Level level) {
  switch (level) {
    case Level::kDebug:
      return "DEBUG";
    case Level::kInfo:
      return "INFO ";
    case Level::kWarn:
      return "WARN ";
    case Level::kError:
      return "ERROR";
  }
  return "?";
}
}  // namespace

void init(std::string_view component, Level min_level) {
  std::lock_guard lock(g_mutex);
  g_component = component;
  g_min_level = min_level;
}

bool parse_level(std::string_view text, Level& out) {
  if (text == "debug")
    out = Level::kDebug;
  else if (text == "info")
    out = Level::kInfo;
  else if (text == "warn")
    out = Level::kWarn;
  else if (text == "error")
    out = Level::kError;
  else
    return false;
  return true;
}

std::string format_line(Level level, std::string_view component, std::string_view text,
                        std::chrono::system_clock::time_point when) {
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(when.time_since_epoch());
  const auto secs = static_cast<std::time_t>(ms.count() / 1000);
  std::tm tm{};
  gmtime_r(&secs, &tm);
  // ISO 8601 in UTC, so lines from hosts in other time zones (or across midnight) sort and
  // compare without guessing the date.
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%S", &tm);
  char line_head[64];
  std::snprintf(line_head, sizeof line_head, "%s.%03dZ %s ", stamp,
                static_cast<int>(ms.count() % 1000), level_name(level));
  std::string line = line_head;
  line.append(component).append(": ").append(text);
  return line;
}

void write(Level level, std::string_view text) {
  if (level < g_min_level) return;
  const auto now = std::chrono::system_clock::now();
  std::lock_guard lock(g_mutex);
  const std::string line = format_line(level, g_component, text, now);
  std::fprintf(stderr, "%s\n", line.c_str());
  std::fflush(stderr);
}

bool Throttle::allow(int64_t now_ns) {
  if (last_ns_ != INT64_MIN && now_ns - last_ns_ < period_ns_) {
    ++suppressed_;
    return false;
  }
  last_ns_ = now_ns;
  return true;
}

}  // namespace stereoball::log
