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

TEST(LogFormat, EveryLevelHasItsFiveCharacterLabel) {
  // Given one instant
  const system_clock::time_point when{milliseconds(1795214401123LL)};
  // When a line is formatted at each level
  // Then the label is padded to five characters, so the text columns line up
  EXPECT_EQ(format_line(Level::kDebug, "c", "x", when).substr(25), "DEBUG c: x");
  EXPECT_EQ(format_line(Level::kInfo, "c", "x", when).substr(25), "INFO  c: x");
  EXPECT_EQ(format_line(Level::kWarn, "c", "x", when).substr(25), "WARN  c: x");
  EXPECT_EQ(format_line(Level::kError, "c", "x", when).substr(25), "ERROR c: x");
}

TEST(LogLevel, ParsesTheFourLowerCaseNamesOnly) {
  // Given a level already set
  Level level = Level::kError;
  // When the command-line names are parsed
  // Then each gives its level, and anything else is refused and leaves the level alone
  EXPECT_TRUE(parse_level("debug", level));
  EXPECT_EQ(level, Level::kDebug);
  EXPECT_TRUE(parse_level("info", level));
  EXPECT_EQ(level, Level::kInfo);
  EXPECT_TRUE(parse_level("warn", level));
  EXPECT_EQ(level, Level::kWarn);
  EXPECT_TRUE(parse_level("error", level));
  EXPECT_EQ(level, Level::kError);
  EXPECT_FALSE(parse_level("INFO", level));
  EXPECT_FALSE(parse_level("warning", level));
  EXPECT_FALSE(parse_level("", level));
  EXPECT_EQ(level, Level::kError);
}

}  // namespace
}  // namespace stereoball::log
