// Sizes a file states are claims: the reader checks them against the file and its limits before
// allocating, verifies chunk indexes and falls back to a linear scan when they are garbage.

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <algorithm>
#include <string>

#include "recorder/core/byte_io.hpp"
#include "recorder/core/crc32.hpp"
#include "recorder/core/file_info.hpp"
#include "recorder/core/reader.hpp"
#include "recorder/core/test_support.hpp"

namespace stereoball::recorder {
namespace {

using testing::make_recording;
using testing::read_all;

constexpr uint64_t kThreeGiB = uint64_t{3} << 30;

testing::Recording recording() {
  WriterParams p;
  p.chunk_size_bytes = 8192;
  return make_recording(p, 2, 120, 400, 7);
}

std::vector<ChunkIndexRecord> chunk_indexes(const std::vector<uint8_t>& bytes) {
  MemorySource source(bytes);
  McapReader reader(source);
  EXPECT_TRUE(reader.open().ok());
  return reader.chunk_indexes();
}

void store_u64(std::vector<uint8_t>& bytes, uint64_t offset, uint64_t value) {
  for (int i = 0; i < 8; ++i) bytes[offset + i] = static_cast<uint8_t>(value >> (8 * i));
}

// Offset of the uncompressed_size field of the chunk record at chunk_start.
uint64_t uncompressed_size_field(uint64_t chunk_start) {
  return chunk_start + kRecordPrefixBytes + 16;  // after message start and end times
}

long peak_rss_kb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

bool has_note(const std::vector<std::string>& notes, const std::string& text) {
  return std::any_of(notes.begin(), notes.end(),
                     [&](const std::string& n) { return n.find(text) != std::string::npos; });
}

// Issue 22: a chunk claiming 3 GiB uncompressed in a small file cost 14 s and 3.1 GB.
TEST(ReaderBounds, GivenAChunkClaiming3GiBWhenReadThenItIsSkippedWithoutAllocating) {
  const auto rec = recording();
  auto bytes = rec.bytes;
  const auto indexes = chunk_indexes(bytes);
  ASSERT_GE(indexes.size(), 3u);
  store_u64(bytes, uncompressed_size_field(indexes[1].chunk_start_offset), kThreeGiB);
  const long rss_before_kb = peak_rss_kb();

  std::vector<std::string> notes;
  const auto got = read_all(bytes, &notes);
  EXPECT_LT(got.size(), rec.messages.size());
  EXPECT_GT(got.size(), 0u) << "the other chunks are still read";
  EXPECT_TRUE(has_note(notes,
                       "claims 3221225472 bytes uncompressed, more than the reader's "
                       "limit of 67108864"))
      << notes.front();

  // With a limit above the claim the zstd frame header still refuses it before allocating.
  MemorySource source(bytes);
  McapReader generous(source, ReaderLimits{uint64_t{4} << 30});
  ASSERT_TRUE(generous.open().ok());
  generous.for_each_message([](const MessageView&) { return true; });
  EXPECT_TRUE(has_note(generous.notes(), "chunk header says 3221225472")) << generous.notes()[0];
  EXPECT_LT(peak_rss_kb() - rss_before_kb, 100'000);
}

// Rewrites every chunk index's offset in the summary and fixes the summary CRC, so the summary
// itself looks valid and only the offsets are garbage.
std::vector<uint8_t> with_garbage_chunk_offsets(const std::vector<uint8_t>& original) {
  auto bytes = original;
  const uint64_t footer_pos = bytes.size() - 8 - kFooterRecordBytes;
  const uint64_t summary_start = load_u64(bytes.data() + footer_pos + kRecordPrefixBytes);
  for (const auto& index : chunk_indexes(original)) {
    for (uint64_t at = summary_start; at + 8 <= footer_pos; ++at) {
      if (load_u64(bytes.data() + at) == index.chunk_start_offset) {
        store_u64(bytes, at, index.chunk_start_offset + 3);  // inside the chunk: not a record
        break;
      }
    }
  }
  const uint64_t crc_at = footer_pos + kRecordPrefixBytes + 16;
  const uint32_t crc = crc32(std::span(bytes).subspan(summary_start, crc_at - summary_start));
  for (int i = 0; i < 4; ++i) bytes[crc_at + i] = static_cast<uint8_t>(crc >> (8 * i));
  return bytes;
}

// Issue 22: garbage chunk-index offsets read 0 messages although every chunk was intact.
TEST(ReaderBounds, GivenGarbageChunkIndexOffsetsWhenReadThenALinearScanReadsEveryMessage) {
  const auto rec = recording();
  const auto bytes = with_garbage_chunk_offsets(rec.bytes);
  std::vector<std::string> notes;
  const auto got = read_all(bytes, &notes);
  ASSERT_EQ(got.size(), rec.messages.size());
  for (size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i], rec.messages[i]) << i;
  EXPECT_TRUE(has_note(notes, "holds no chunk of")) << (notes.empty() ? "" : notes[0]);
  EXPECT_TRUE(has_note(notes, "scanned linearly"));
}

TEST(ReaderBounds, GivenEveryChunkCorruptWhenSummarizedThenNothingReadableIsReported) {
  const auto rec = recording();
  auto bytes = rec.bytes;
  const auto indexes = chunk_indexes(bytes);
  for (const auto& index : indexes)
    store_u64(bytes, uncompressed_size_field(index.chunk_start_offset), kThreeGiB);
  MemorySource source(bytes);
  const auto info = collect_file_info(source);
  ASSERT_TRUE(info) << info.error();
  EXPECT_EQ(info->messages, 0u);
  EXPECT_EQ(info->listed_messages, rec.messages.size());
  EXPECT_TRUE(info->nothing_readable());
  const std::string text = format_file_info(*info, "x.mcap");
  EXPECT_NE(text.find("complete:  NO (closed properly, but not every message listed could be "
                      "read)"),
            std::string::npos)
      << text;
}

TEST(ReaderBounds, GivenAnIntactOrAnEmptyRecordingWhenSummarizedThenItIsReadable) {
  const auto rec = recording();
  MemorySource source(rec.bytes);
  const auto info = collect_file_info(source);
  ASSERT_TRUE(info);
  EXPECT_FALSE(info->nothing_readable());
  const auto empty = make_recording(WriterParams{}, 1, 0, 10);
  MemorySource empty_source(empty.bytes);
  const auto empty_info = collect_file_info(empty_source);
  ASSERT_TRUE(empty_info) << empty_info.error();
  EXPECT_FALSE(empty_info->nothing_readable()) << "a closed empty recording is not an error";
}

TEST(ReaderBounds, GivenARecordLargerThanTheLimitWhenScannedThenItIsSkippedWithANote) {
  WriterParams p;
  p.chunk_size_bytes = 8192;
  const auto rec = make_recording(p, 1, 40, 400, 3);
  auto bytes = rec.bytes;
  bytes.resize(bytes.size() - 8 - kFooterRecordBytes);  // no footer: a linear scan
  MemorySource source(bytes);
  McapReader reader(source, ReaderLimits{4096});
  ASSERT_TRUE(reader.open().ok());
  EXPECT_TRUE(has_note(reader.notes(), "more than the reader's limit of 4096; skipped"));
}

}  // namespace
}  // namespace stereoball::recorder
