#include "recorder/core/records.hpp"

#include <gtest/gtest.h>

#include "recorder/core/byte_io.hpp"

namespace stereoball::recorder {
namespace {

// Splits one encoded record into opcode and content, checking the length prefix.
RecordView split(const std::vector<uint8_t>& bytes) {
  EXPECT_GE(bytes.size(), kRecordPrefixBytes);
  EXPECT_EQ(load_u64(bytes.data() + 1), bytes.size() - kRecordPrefixBytes);
  return {bytes[0], std::span(bytes).subspan(kRecordPrefixBytes)};
}

TEST(Records, GivenAChannelWithMetadataWhenEncodedAndParsedThenFieldsSurvive) {
  ChannelRecord c{7, 3, "stereo/frame", "cdr", {{"qos", "best_effort"}, {"k", ""}}};
  std::vector<uint8_t> out;
  append_channel(out, c);
  const auto r = split(out);
  EXPECT_EQ(r.opcode, static_cast<uint8_t>(Opcode::kChannel));
  const auto parsed = parse_channel(r.content);
  ASSERT_TRUE(parsed);
  EXPECT_EQ(*parsed, c);
}

TEST(Records, GivenASchemaWhenEncodedAndParsedThenDataIsByteEqual) {
  SchemaRecord s{2, "stereoball::msg::BallTrack", "omgidl", {'m', 'o', 'd', 0, 0xFF}};
  std::vector<uint8_t> out;
  append_schema(out, s);
  const auto parsed = parse_schema(split(out).content);
  ASSERT_TRUE(parsed);
  EXPECT_EQ(*parsed, s);
}

TEST(Records, GivenAChunkIndexWhenEncodedAndParsedThenEveryFieldSurvives) {
  ChunkIndexRecord c{10, 20, 300, 4000, {{1, 5000}, {4, 5050}}, 100, "zstd", 3900, 9000};
  std::vector<uint8_t> out;
  append_chunk_index(out, c);
  const auto p = parse_chunk_index(split(out).content);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->message_start_time_ns, 10u);
  EXPECT_EQ(p->message_end_time_ns, 20u);
  EXPECT_EQ(p->chunk_start_offset, 300u);
  EXPECT_EQ(p->chunk_length, 4000u);
  EXPECT_EQ(p->message_index_offsets, c.message_index_offsets);
  EXPECT_EQ(p->message_index_length, 100u);
  EXPECT_EQ(p->compression, "zstd");
  EXPECT_EQ(p->compressed_size, 3900u);
  EXPECT_EQ(p->uncompressed_size, 9000u);
}

TEST(Records, GivenStatisticsWhenEncodedAndParsedThenCountsSurvive) {
  StatisticsRecord s{42, 2, 3, 0, 0, 5, 100, 900, {{1, 40}, {2, 2}}};
  std::vector<uint8_t> out;
  append_statistics(out, s);
  const auto p = parse_statistics(split(out).content);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->message_count, 42u);
  EXPECT_EQ(p->schema_count, 2);
  EXPECT_EQ(p->channel_count, 3u);
  EXPECT_EQ(p->chunk_count, 5u);
  EXPECT_EQ(p->message_start_time_ns, 100u);
  EXPECT_EQ(p->message_end_time_ns, 900u);
  EXPECT_EQ(p->channel_message_counts, s.channel_message_counts);
}

TEST(Records, GivenAMessageWhenEncodedThenLayoutFollowsTheSpec) {
  const std::vector<uint8_t> payload = {1, 2, 3};
  std::vector<uint8_t> out;
  append_message(out, MessageView{0x0102, 0x03040506, 7, 8, payload});
  // opcode, u64 length, u16 channel, u32 sequence, u64 log time, u64 publish time, data.
  ASSERT_EQ(out.size(), 1u + 8 + 2 + 4 + 8 + 8 + 3);
  EXPECT_EQ(out[0], 0x05);
  EXPECT_EQ(out[9], 0x02);  // channel id, little-endian
  EXPECT_EQ(out[10], 0x01);
  EXPECT_EQ(out[11], 0x06);  // sequence, little-endian
  EXPECT_EQ(out[15], 7);     // log time
  EXPECT_EQ(out[23], 8);     // publish time
  const auto m = parse_message(split(out).content);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->log_time_ns, 7u);
  EXPECT_EQ(m->publish_time_ns, 8u);
  EXPECT_TRUE(std::equal(m->data.begin(), m->data.end(), payload.begin(), payload.end()));
}

TEST(Records, GivenMessageIndexAndSummaryOffsetWhenRoundTrippedThenEqual) {
  std::vector<uint8_t> out;
  append_message_index(out, MessageIndexRecord{9, {{1, 0}, {2, 40}}});
  const auto mi = parse_message_index(split(out).content);
  ASSERT_TRUE(mi);
  EXPECT_EQ(mi->channel_id, 9);
  EXPECT_EQ(mi->entries, (std::vector<std::pair<uint64_t, uint64_t>>{{1, 0}, {2, 40}}));
  out.clear();
  append_summary_offset(out, SummaryOffsetRecord{0x08, 1234, 56});
  const auto so = parse_summary_offset(split(out).content);
  ASSERT_TRUE(so);
  EXPECT_EQ(so->group_opcode, 0x08);
  EXPECT_EQ(so->group_start, 1234u);
  EXPECT_EQ(so->group_length, 56u);
}

TEST(Records, GivenTruncatedContentWhenParsedThenEveryParserFails) {
  std::vector<uint8_t> out;
  append_chunk_index(out, ChunkIndexRecord{1, 2, 3, 4, {{1, 2}}, 5, "zstd", 6, 7});
  auto content = split(out).content;
  for (size_t n = 0; n < content.size(); ++n) {
    EXPECT_FALSE(parse_chunk_index(content.first(n))) << "prefix " << n;
  }
  out.clear();
  append_channel(out, ChannelRecord{1, 1, "t", "cdr", {{"a", "b"}}});
  content = split(out).content;
  for (size_t n = 0; n < content.size(); ++n) EXPECT_FALSE(parse_channel(content.first(n)));
}

TEST(Records, GivenOpcodesWhenNamedThenKnownAndUnknownAreReadable) {
  EXPECT_EQ(opcode_name(0x06), "Chunk");
  EXPECT_EQ(opcode_name(0x0F), "DataEnd");
  EXPECT_EQ(opcode_name(0x42), "unknown 0x42");
}

}  // namespace
}  // namespace stereoball::recorder
