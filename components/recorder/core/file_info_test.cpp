#include "recorder/core/file_info.hpp"

#include <gtest/gtest.h>

#include "recorder/core/test_support.hpp"

namespace stereoball::recorder {
namespace {

TEST(FileInfo, GivenARecordingWhenSummarizedThenCountsRatesAndSizesMatchTheInput) {
  // Given 3 channels with known messages
  WriterParams p;
  p.chunk_size_bytes = 8192;
  const auto rec = testing::make_recording(p, 3, 400, 700, 4);
  MemorySource source(rec.bytes);
  // When summarized
  const auto info = collect_file_info(source);
  ASSERT_TRUE(info) << info.error();
  // Then every figure agrees with what was written
  EXPECT_TRUE(info->complete);
  EXPECT_EQ(info->messages, 400u);
  EXPECT_EQ(info->start_ns, rec.messages.front().log_time_ns);
  EXPECT_EQ(info->end_ns, rec.messages.back().log_time_ns);
  ASSERT_EQ(info->topics.size(), 3u);
  for (const auto& t : info->topics) {
    uint64_t n = 0, bytes = 0, first = 0, last = 0;
    for (const auto& m : rec.messages) {
      if ("topic/" + std::to_string(m.channel_id - 1) != t.topic) continue;
      if (n++ == 0) first = m.log_time_ns;
      last = m.log_time_ns;
      bytes += m.data.size();
    }
    EXPECT_EQ(t.messages, n) << t.topic;
    EXPECT_EQ(t.bytes, bytes) << t.topic;
    EXPECT_EQ(t.type, "test::Msg");
    EXPECT_NEAR(t.rate_hz, (n - 1) * 1e9 / double(last - first), 1e-9) << t.topic;
  }
  const std::string text = format_file_info(*info, "x.mcap");
  EXPECT_NE(text.find("complete:  yes"), std::string::npos);
  EXPECT_NE(text.find("topic/2"), std::string::npos);
}

TEST(FileInfo, GivenATruncatedRecordingWhenSummarizedThenItSaysIncompleteAndLinear) {
  const auto rec = testing::make_recording(WriterParams{}, 2, 50, 100);
  std::vector<uint8_t> cut(rec.bytes.begin(), rec.bytes.end() - 20);
  MemorySource source(cut);
  const auto info = collect_file_info(source);
  ASSERT_TRUE(info);
  EXPECT_FALSE(info->complete);
  EXPECT_FALSE(info->indexed);
  const std::string text = format_file_info(*info, "cut.mcap");
  EXPECT_NE(text.find("complete:  NO"), std::string::npos);
  EXPECT_NE(text.find("no summary, scanned linearly"), std::string::npos);
}

TEST(FileInfo, GivenATimestampWhenFormattedThenUtcWithNanoseconds) {
  EXPECT_EQ(format_utc(86'400'000'000'001ull), "1970-01-02 00:00:00.000000001 UTC");
}

}  // namespace
}  // namespace stereoball::recorder
