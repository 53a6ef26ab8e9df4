#include <gtest/gtest.h>

#include "recorder/core/reader.hpp"
#include "recorder/core/test_support.hpp"
#include "recorder/core/writer.hpp"

namespace stereoball::recorder {
namespace {

using testing::make_recording;
using testing::read_all;
using testing::StoredMessage;

WriterParams small_chunks(Compression c = Compression::kZstd) {
  WriterParams p;
  p.chunk_size_bytes = 16 * 1024;
  p.compression = c;
  return p;
}

TEST(WriterReader, GivenManyMessagesOnSeveralChannelsWhenReadBackThenByteEqualAndInOrder) {
  // Given 2000 messages of up to 2 KiB on 5 channels, in small zstd chunks
  const auto rec = make_recording(small_chunks(), 5, 2000, 2048);
  ASSERT_EQ(rec.messages.size(), 2000u);
  // When read back
  MemorySource source(rec.bytes);
  McapReader reader(source);
  ASSERT_TRUE(reader.open().ok());
  std::vector<StoredMessage> got;
  ASSERT_TRUE(testing::read_all(reader, got).ok());
  // Then everything is identical, read through the index, with no problem noted
  EXPECT_EQ(got, rec.messages);
  EXPECT_TRUE(reader.summary().complete);
  EXPECT_TRUE(reader.summary().indexed);
  EXPECT_TRUE(reader.notes().empty()) << reader.notes().front();
  EXPECT_GT(reader.chunk_indexes().size(), 10u);
  EXPECT_TRUE(reader.check_message_indexes().ok());
}

TEST(WriterReader, GivenARecordingWhenOpenedThenStatisticsMatchWhatWasWritten) {
  const auto rec = make_recording(small_chunks(), 3, 500, 512);
  MemorySource source(rec.bytes);
  McapReader reader(source);
  ASSERT_TRUE(reader.open().ok());
  const auto& s = reader.summary().statistics;
  EXPECT_EQ(s.message_count, 500u);
  EXPECT_EQ(s.channel_count, 3u);
  EXPECT_EQ(s.schema_count, 1);
  EXPECT_EQ(s.chunk_count, rec.messages_after_chunk.size());
  EXPECT_EQ(s.message_start_time_ns, rec.messages.front().log_time_ns);
  EXPECT_EQ(s.message_end_time_ns, rec.messages.back().log_time_ns);
  std::map<uint16_t, uint64_t> counts;
  for (const auto& m : rec.messages) ++counts[m.channel_id];
  EXPECT_EQ(s.channel_message_counts, counts);
  ASSERT_EQ(reader.summary().channels.size(), 3u);
  EXPECT_EQ(reader.summary().channels.at(1).topic, "topic/0");
  EXPECT_EQ(reader.summary().channels.at(1).message_encoding, "cdr");
  const auto& schema = reader.summary().schemas.at(1);
  EXPECT_EQ(schema.encoding, "omgidl");
  EXPECT_EQ(std::string(schema.data.begin(), schema.data.end()), "struct Msg {};");
}

TEST(WriterReader, GivenUncompressedChunksWhenReadBackThenByteEqual) {
  const auto rec = make_recording(small_chunks(Compression::kNone), 4, 300, 4096);
  EXPECT_EQ(read_all(rec.bytes), rec.messages);
}

TEST(WriterReader, GivenTheSameDataWhenCompressedThenTheFileIsSmaller) {
  const auto zstd = make_recording(small_chunks(Compression::kZstd), 2, 300, 4096);
  const auto none = make_recording(small_chunks(Compression::kNone), 2, 300, 4096);
  EXPECT_LT(zstd.bytes.size(), none.bytes.size());
}

TEST(WriterReader, GivenAMessageLargerThanTheChunkSizeWhenWrittenThenItGetsItsOwnChunk) {
  WriterParams p = small_chunks();
  p.chunk_size_bytes = 1024;
  const auto rec = make_recording(p, 1, 20, 100'000);
  EXPECT_EQ(read_all(rec.bytes), rec.messages);
  EXPECT_GE(rec.messages_after_chunk.size(), 15u);
}

TEST(WriterReader, GivenNoMessagesWhenClosedThenAValidEmptyFile) {
  MemorySink sink;
  McapWriter writer(WriterParams{});
  ASSERT_TRUE(writer.open(sink).ok());
  ASSERT_TRUE(writer.close().ok());
  MemorySource source(sink.bytes());
  McapReader reader(source);
  ASSERT_TRUE(reader.open().ok());
  EXPECT_TRUE(reader.summary().complete);
  EXPECT_EQ(reader.summary().statistics.message_count, 0u);
  EXPECT_EQ(reader.summary().header.library, "stereoball-recorder");
}

TEST(WriterReader, GivenBadParamsWhenValidatedThenTheFieldIsNamed) {
  WriterParams p;
  p.chunk_size_bytes = 10;
  ASSERT_FALSE(p.validate().ok());
  EXPECT_NE(p.validate().error().find("chunk_size_bytes"), std::string::npos);
  p = {};
  p.zstd_level = 40;
  ASSERT_FALSE(p.validate().ok());
  EXPECT_NE(p.validate().error().find("zstd_level"), std::string::npos);
  MemorySink sink;
  EXPECT_FALSE(McapWriter(p).open(sink).ok());
}

TEST(WriterReader, GivenUnknownIdsWhenUsedThenTheWriterRefuses) {
  MemorySink sink;
  McapWriter writer(WriterParams{});
  ASSERT_TRUE(writer.open(sink).ok());
  EXPECT_FALSE(writer.add_channel(5, "t", "cdr"));
  const std::vector<uint8_t> data = {1};
  EXPECT_FALSE(writer.write({1, 0, 1, 1, data}).ok());
  EXPECT_FALSE(writer.write({0, 0, 1, 1, data}).ok());
}

// Sink that fails once a byte budget is used up, like a full disk.
class FullDiskSink : public Sink {
 public:
  explicit FullDiskSink(size_t budget) : budget_(budget) {}
  Status write(std::span<const uint8_t> bytes) override {
    if (bytes_.size() + bytes.size() > budget_) return Error{"No space left on device"};
    bytes_.insert(bytes_.end(), bytes.begin(), bytes.end());
    return {};
  }
  std::vector<uint8_t> bytes_;

 private:
  size_t budget_;
};

TEST(WriterReader, GivenADiskThatFillsUpWhenWritingThenErrorIsReportedAndThePrefixIsReadable) {
  FullDiskSink sink(60'000);
  McapWriter writer(small_chunks(Compression::kNone));
  ASSERT_TRUE(writer.open(sink).ok());
  const auto schema = writer.add_schema("S", "omgidl", std::string_view("struct S {};"));
  const auto channel = writer.add_channel(schema.value(), "t", "cdr");
  std::vector<uint8_t> data(1000, 0xAB);
  Status err;
  uint64_t written = 0;
  for (int i = 0; i < 200 && err.ok(); ++i) {
    data[0] = static_cast<uint8_t>(i);
    err = writer.write({channel.value(), static_cast<uint32_t>(i), 1000u + i, 1000u + i, data});
    if (err.ok()) ++written;
  }
  ASSERT_FALSE(err.ok());
  EXPECT_NE(err.error().find("No space left"), std::string::npos);
  EXPECT_FALSE(writer.write({channel.value(), 0, 1, 1, data}).ok());  // stays failed
  std::vector<std::string> notes;
  const auto got = read_all(sink.bytes_, &notes);
  EXPECT_GT(got.size(), 0u);
  EXPECT_LE(got.size(), written);
  for (size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i].sequence, i);
  ASSERT_FALSE(notes.empty());
  EXPECT_NE(notes.front().find("no summary, scanned linearly"), std::string::npos);
}

TEST(WriterReader, GivenAnUnclosedWriterWhenReadThenCompletedChunksAreReadLinearly) {
  // Given a writer whose process "died" after some chunks (never closed)
  MemorySink sink;
  McapWriter writer(small_chunks());
  ASSERT_TRUE(writer.open(sink).ok());
  const auto schema = writer.add_schema("S", "omgidl", std::string_view("struct S {};"));
  const auto channel = writer.add_channel(schema.value(), "t", "cdr");
  std::vector<uint8_t> data(3000, 1);
  for (uint32_t i = 0; i < 50; ++i) {
    data[1] = static_cast<uint8_t>(i);
    ASSERT_TRUE(writer.write({channel.value(), i, i + 1u, i + 1u, data}).ok());
  }
  const uint64_t in_chunks = writer.stats().chunks;
  ASSERT_GT(in_chunks, 0u);
  // When the file as it stands is read
  MemorySource source(sink.bytes());
  McapReader reader(source);
  ASSERT_TRUE(reader.open().ok());
  // Then it is marked incomplete, and every message of the finished chunks is there
  EXPECT_FALSE(reader.summary().complete);
  EXPECT_FALSE(reader.summary().indexed);
  // A message record is 9 (prefix) + 22 (fields) + payload bytes.
  const uint64_t record_bytes = 3000 + 31;
  const uint64_t per_chunk = (16 * 1024 + record_bytes - 1) / record_bytes;
  EXPECT_EQ(reader.summary().statistics.message_count, in_chunks * per_chunk);
  EXPECT_EQ(reader.summary().channels.at(channel.value()).topic, "t");
}

// Flips one byte in the middle of the first occurrence of payload inside the file.
void corrupt_payload(std::vector<uint8_t>& bytes, const std::vector<uint8_t>& payload) {
  auto it = std::search(bytes.begin(), bytes.end(), payload.begin(), payload.end());
  ASSERT_NE(it, bytes.end());
  *(it + payload.size() / 2) ^= 0xFF;
}

TEST(WriterReader, GivenACorruptedChunkWhenReadThenTheCrcMismatchIsReportedAndOthersSurvive) {
  auto rec = make_recording(small_chunks(Compression::kNone), 2, 200, 1000, 3);
  const auto largest =
      std::max_element(rec.messages.begin(), rec.messages.end(),
                       [](const auto& a, const auto& b) { return a.data.size() < b.data.size(); });
  corrupt_payload(rec.bytes, largest->data);
  std::vector<std::string> notes;
  const auto got = read_all(rec.bytes, &notes);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("CRC mismatch"), std::string::npos) << notes[0];
  EXPECT_LT(got.size(), rec.messages.size());
  EXPECT_GT(got.size(), rec.messages.size() / 2);
  for (const auto& m : got) EXPECT_EQ(m, rec.messages[m.sequence]);
}

TEST(WriterReader, GivenACorruptedSummaryWhenOpenedThenMismatchIsNotedAndLinearScanReadsAll) {
  auto rec = make_recording(small_chunks(), 2, 100, 100);
  // The summary holds a second copy of "topic/1"; the last occurrence is in the summary.
  const std::string topic = "topic/1";
  auto it = std::find_end(rec.bytes.begin(), rec.bytes.end(), topic.begin(), topic.end());
  ASSERT_NE(it, rec.bytes.end());
  *it = 'X';
  std::vector<std::string> notes;
  EXPECT_EQ(read_all(rec.bytes, &notes), rec.messages);
  ASSERT_FALSE(notes.empty());
  EXPECT_NE(notes[0].find("summary CRC mismatch"), std::string::npos) << notes[0];
  EXPECT_NE(notes[0].find("scanned linearly"), std::string::npos);
}

TEST(WriterReader, GivenAVisitorThatStopsWhenIteratingThenNoFurtherMessagesAreDelivered) {
  const auto rec = make_recording(small_chunks(), 2, 300, 300);
  MemorySource source(rec.bytes);
  McapReader reader(source);
  ASSERT_TRUE(reader.open().ok());
  int seen = 0;
  ASSERT_TRUE(reader.for_each_message([&](const MessageView&) { return ++seen < 10; }).ok());
  EXPECT_EQ(seen, 10);
}

}  // namespace
}  // namespace stereoball::recorder

namespace stereoball::recorder {
namespace {

TEST(WriterReader, GivenADataSectionCrcWhenADataRecordIsCorruptedThenTheScanReportsAMismatch) {
  WriterParams p;
  p.data_section_crc = true;
  auto rec = testing::make_recording(p, 2, 50, 100);
  // Dropping the footer makes the reader scan the data section (and check its CRC).
  std::vector<uint8_t> intact(rec.bytes.begin(), rec.bytes.end() - 8);
  std::vector<std::string> notes;
  EXPECT_EQ(testing::read_all(intact, &notes), rec.messages);
  for (const auto& n : notes) EXPECT_EQ(n.find("CRC mismatch"), std::string::npos) << n;
  // The first "test::Msg" is the schema record in the data section (outside any chunk).
  const std::string name = "test::Msg";
  auto it = std::search(intact.begin(), intact.end(), name.begin(), name.end());
  ASSERT_NE(it, intact.end());
  *it = 'X';
  EXPECT_EQ(testing::read_all(intact, &notes), rec.messages);
  bool reported = false;
  for (const auto& n : notes) reported |= n.find("data section CRC mismatch") != std::string::npos;
  EXPECT_TRUE(reported);
}

}  // namespace
}  // namespace stereoball::recorder
