#include <gtest/gtest.h>

#include <chrono>

#include "common/util/log.hpp"

namespace stereoball::log {
namespace {

using std::chrono::milliseconds;
using std::chrono::system_clock;

TEST(LogFormat, LineStartsWithIsoDateInUtcWithMilliseconds) {
  // Given 2026-11-20 22:40:01.123 UTC (1795214401 s since the epoch)
  const system_clock::time_point when{milliseconds(1795214401123LL)};
  // When a line is formatted
  const std::string line = format_line(Level::kWarn, "tracker", "ball lost", when);
  // Then it carries the full date, not only the time of day
  EXPECT_EQ(line, "2026-11-20T22:40:01.123Z WARN  tracker: ball lost");
}

TEST(LogFormat, MillisecondsArePaddedAndDatesRollOver) {
  // Given the last millisecond-padded instant before midnight and the first after
  const system_clock::time_point before{milliseconds(1795219199007LL)};
  const system_clock::time_point after{milliseconds(1795219200000LL)};
  // Then the date changes with the day and milliseconds keep three digits
  EXPECT_EQ(format_line(Level::kInfo, "sim", "x", before).substr(0, 24),
            "2026-11-20T23:59:59.007Z");
  EXPECT_EQ(format_line(Level::kInfo, "sim", "x", after).substr(0, 24), "2026-11-21T00:00:00.000Z");
}

}  // namespace
}  // namespace stereoball::log
