#include <gtest/gtest.h>

#include "recorder/core/reader.hpp"
#include "recorder/core/test_support.hpp"

namespace stereoball::recorder {
namespace {

using testing::make_recording;
using testing::StoredMessage;

// Messages a reader must recover from the first cut bytes: those of every chunk whose record
// lies entirely before the cut.
size_t expected_prefix(const testing::Recording& rec, const std::vector<ChunkIndexRecord>& chunks,
                       uint64_t cut) {
  size_t complete = 0;
  for (size_t i = 0; i < chunks.size(); ++i) {
    if (chunks[i].chunk_start_offset + chunks[i].chunk_length <= cut) complete = i + 1;
  }
  return complete == 0 ? 0 : rec.messages_after_chunk[complete - 1];
}

class Truncation : public ::testing::TestWithParam<Compression> {
 protected:
  void SetUp() override {
    WriterParams p;
    p.chunk_size_bytes = 2048;
    p.compression = GetParam();
    rec_ = make_recording(p, 3, 120, 300, 11);
    MemorySource source(rec_.bytes);
    McapReader reader(source);
    ASSERT_TRUE(reader.open().ok());
    chunks_ = reader.chunk_indexes();
    ASSERT_EQ(chunks_.size(), rec_.messages_after_chunk.size());
    ASSERT_GT(chunks_.size(), 3u);
  }

  // Reads the first cut bytes and checks the result is exactly the complete prefix.
  void check_cut(uint64_t cut) {
    std::vector<uint8_t> bytes(rec_.bytes.begin(), rec_.bytes.begin() + cut);
    MemorySource source(bytes);
    McapReader reader(source);
    if (cut < 8 + 9) {  // not even magic and a header prefix
      EXPECT_FALSE(reader.open().ok()) << "cut " << cut;
      return;
    }
    const auto header_end = 8 + 9 + 4 + 0 + 4 + std::string("stereoball-recorder").size();
    if (cut < header_end) {
      ASSERT_FALSE(reader.open().ok()) << "cut " << cut;
      EXPECT_NE(reader.open().error().find("truncated"), std::string::npos);
      return;
    }
    ASSERT_TRUE(reader.open().ok()) << "cut " << cut;
    std::vector<StoredMessage> got;
    ASSERT_TRUE(testing::read_all(reader, got).ok());
    const size_t want = expected_prefix(rec_, chunks_, cut);
    ASSERT_EQ(got.size(), want) << "cut " << cut;
    EXPECT_TRUE(std::equal(got.begin(), got.end(), rec_.messages.begin())) << "cut " << cut;
    EXPECT_EQ(reader.summary().statistics.message_count, want) << "cut " << cut;
    EXPECT_FALSE(reader.summary().complete) << "cut " << cut;
    ASSERT_FALSE(reader.notes().empty());
    EXPECT_NE(reader.notes().front().find("no summary, scanned linearly"), std::string::npos);
  }

  testing::Recording rec_;
  std::vector<ChunkIndexRecord> chunks_;
};

TEST_P(Truncation, GivenEveryCutInsideTheLastChunkWhenReadThenTheCompletePrefixIsReturned) {
  const auto& last = chunks_.back();
  const uint64_t begin = last.chunk_start_offset;
  const uint64_t end = begin + last.chunk_length + last.message_index_length;
  for (uint64_t cut = begin; cut <= end; ++cut) check_cut(cut);
}

TEST_P(Truncation, GivenCutsAcrossTheWholeFileWhenReadThenNeverCrashesAndKeepsThePrefix) {
  // Every 13th byte from the start to just before the end (the full file is complete).
  for (uint64_t cut = 0; cut < rec_.bytes.size(); cut += 13) check_cut(cut);
  check_cut(rec_.bytes.size() - 1);
}

INSTANTIATE_TEST_SUITE_P(Compressions, Truncation,
                         ::testing::Values(Compression::kZstd, Compression::kNone));

}  // namespace
}  // namespace stereoball::recorder
