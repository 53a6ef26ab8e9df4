#include "common/util/log.hpp"

#include <chrono>
#include <cstdio>
#include <ctime>
#include <mutex>

#include "common/util/enum_names.hpp"

namespace stereoball::log {
namespace {
std::mutex g_mutex;
std::string g_component = "stereoball";
Level g_min_level = Level::kInfo;

// Names in log lines, padded to one width so the text columns line up.
constexpr util::EnumName<Level> kLevelLabels[] = {
    {Level::kDebug, "DEBUG"},
    {Level::kInfo, "INFO "},
    {Level::kWarn, "WARN "},
    {Level::kError, "ERROR"},
};
// Names on the command line (--log-level).
constexpr util::EnumName<Level> kLevelNames[] = {
    {Level::kDebug, "debug"},
    {Level::kInfo, "info"},
    {Level::kWarn, "warn"},
    {Level::kError, "error"},
};
}  // namespace

void init(std::string_view component, Level min_level) {
  std::lock_guard lock(g_mutex);
  g_component = component;
  g_min_level = min_level;
}

bool parse_level(std::string_view text, Level& out) {
  const auto level = util::value_of(kLevelNames, text);
  if (level) out = *level;
  return level.has_value();
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
  const std::string_view label = util::name_of(kLevelLabels, level, "?");
  std::snprintf(line_head, sizeof line_head, "%s.%03dZ %.*s ", stamp,
                static_cast<int>(ms.count() % 1000), static_cast<int>(label.size()), label.data());
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
