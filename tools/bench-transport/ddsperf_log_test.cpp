#include "ddsperf_log.hpp"

#include <gtest/gtest.h>

namespace bt = stereoball::bench_transport;

namespace {

std::string ping_line(double t, const char* p50, const char* p99, int count) {
  return "[7364] " + std::to_string(t) +
         "  vm:7352 size 1843200 mean 29147.874us min 1973.783us 50% " + p50 +
         "us 90% 76638.343us 99% " + p99 + "us max 269488.820us cnt " + std::to_string(count) +
         "\n";
}

}  // namespace

TEST(DdsperfPingLog, FirstSecondIsWarmUpAndOtherLinesAreIgnored) {
  // Given a log with participant and resource lines and three per-second ping lines
  const std::string log =
      "[7364] participant vm:7364: new (self)\n" + ping_line(2.0, "9000.5", "20000.25", 40) +
      "[7364] 2.000  rss:18.0MB vcsw:1024 ivcsw:700 ddsperf:1%+2%\n" +
      ping_line(3.0, "2495.830", "7000.5", 14) + ping_line(4.0, "2600.0", "8000.0", 12);
  // When it is read
  const bt::DdsperfSeconds s = bt::parse_ddsperf_ping_log(log);
  // Then the first second is left out and the others give their 50 % and 99 %
  EXPECT_EQ(s.seconds, 2u);
  EXPECT_EQ(s.count, 26u);
  ASSERT_EQ(s.medians_us.size(), 2u);
  EXPECT_DOUBLE_EQ(s.medians_us[0], 2495.830);
  EXPECT_DOUBLE_EQ(s.p99s_us[1], 8000.0);
  EXPECT_EQ(s.sparse_seconds, 0u);
}

TEST(DdsperfPingLog, SecondsWithAHandfulOfRoundTripsCountOnlyTowardTheRate) {
  // Given a loaded machine: after the first second, one second with a single round trip and
  // one with six, where the 99th percentile is just the slowest of them
  const std::string log = ping_line(2.0, "1.0", "2.0", 14) +
                          ping_line(3.0, "368109.6", "368109.6", 1) +
                          ping_line(4.0, "87852.1", "197185.2", bt::kMinSamplesPerSecond - 4) +
                          ping_line(5.0, "3000.0", "9000.0", bt::kMinSamplesPerSecond);
  // When it is read
  const bt::DdsperfSeconds s = bt::parse_ddsperf_ping_log(log);
  // Then only the second with enough round trips gives latency figures, every one the rate
  EXPECT_EQ(s.seconds, 3u);
  EXPECT_EQ(s.sparse_seconds, 2u);
  EXPECT_EQ(s.count, 1u + (bt::kMinSamplesPerSecond - 4) + bt::kMinSamplesPerSecond);
  ASSERT_EQ(s.medians_us.size(), 1u);
  EXPECT_DOUBLE_EQ(s.medians_us[0], 3000.0);
  EXPECT_DOUBLE_EQ(s.p99s_us[0], 9000.0);
}

TEST(DdsperfPingLog, ALogWithoutPingLinesHasNoSeconds) {
  // Given a ping that never matched its pong
  const std::string log =
      "[7286] participant vm:7286: new (self)\n[7286] 2.000  rss:15.7MB vcsw:9 ivcsw:10\n";
  // When it is read
  const bt::DdsperfSeconds s = bt::parse_ddsperf_ping_log(log);
  // Then there is nothing to report
  EXPECT_EQ(s.seconds, 0u);
  EXPECT_EQ(s.count, 0u);
  EXPECT_TRUE(s.medians_us.empty());
}
