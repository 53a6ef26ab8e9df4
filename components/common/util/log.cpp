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

void write(Level level, std::string_view text) {
  if (level < g_min_level) return;
  const auto now = std::chrono::system_clock::now();
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch());
  const std::time_t secs = static_cast<std::time_t>(ms.count() / 1000);
  std::tm tm{};
  gmtime_r(&secs, &tm);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%H:%M:%S", &tm);
  std::lock_guard lock(g_mutex);
  std::fprintf(stderr, "%s.%03d %s %s: %.*s\n", stamp, static_cast<int>(ms.count() % 1000),
               level_name(level), g_component.c_str(), static_cast<int>(text.size()), text.data());
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
