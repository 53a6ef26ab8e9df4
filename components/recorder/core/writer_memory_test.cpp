// The writer's memory does not grow with the length of a recording: chunk buffers are sized
// once, and the summary's chunk indexes go to a spill in blocks (the file stays the same).

#include <gtest/gtest.h>

#include "recorder/core/reader.hpp"
#include "recorder/core/test_support.hpp"
#include "recorder/core/writer.hpp"

namespace stereoball::recorder {
namespace {

WriterParams tiny_chunk_params() {
  WriterParams p;
  p.chunk_size_bytes = 1024;
  return p;
}

// A writer on one channel whose messages (size bytes each, value i) close a chunk each.
struct OneChannelWriter {
  MemorySink sink;
  McapWriter writer{tiny_chunk_params()};
  uint16_t channel = 0;
  uint64_t t = 1'000'000'000;

  explicit OneChannelWriter(Spill* spill) {
    EXPECT_TRUE(writer.open(sink, spill).ok());
    const auto schema = writer.add_schema("t::M", "omgidl", std::string_view("struct M {};"));
    channel = writer.add_channel(schema.value(), "m", "cdr").value();
  }
  // Writes one message and closes its chunk.
  void chunk(size_t size) {
    const std::vector<uint8_t> data(size, static_cast<uint8_t>(t));
    t += 1000;
    ASSERT_TRUE(writer.write({channel, 0, t, t, data}).ok());
    ASSERT_TRUE(writer.flush_chunk().ok());
  }
};

// A spill whose writes fail, as a full disk would.
class FullSpill : public Spill {
 public:
  Status write(std::span<const uint8_t>) override { return Error{"no space left on device"}; }
  uint64_t size() const override { return 0; }
  Status read(uint64_t, std::span<uint8_t>) override { return Error{"nothing written"}; }
};

TEST(WriterMemory, GivenAnIndexSpillWhenAFileIsWrittenThenItIsByteIdenticalToOneWithout) {
  // Given the same 20000 messages in 1 KiB chunks, written with and without a spill
  MemorySpill spill;
  const auto spilled = testing::make_recording(tiny_chunk_params(), 3, 20000, 300, 7, &spill);
  const auto in_memory = testing::make_recording(tiny_chunk_params(), 3, 20000, 300, 7);
  // Then the chunk indexes went through the spill, and the two files are the same bytes
  ASSERT_FALSE(spilled.bytes.empty());
  EXPECT_GT(spill.size(), 2 * McapWriter::kIndexBlockBytes);
  EXPECT_EQ(spilled.bytes, in_memory.bytes);
  // And the file is read through its index, complete, with every message
  MemorySource source(spilled.bytes);
  McapReader reader(source);
  ASSERT_TRUE(reader.open().ok());
  EXPECT_TRUE(reader.summary().complete);
  EXPECT_TRUE(reader.summary().indexed);
  EXPECT_TRUE(reader.notes().empty()) << reader.notes().front();
  EXPECT_EQ(reader.chunk_indexes().size(), spilled.messages_after_chunk.size());
  EXPECT_EQ(reader.summary().statistics.chunk_count, spilled.messages_after_chunk.size());
  EXPECT_EQ(testing::read_all(spilled.bytes), spilled.messages);
}

TEST(WriterMemory, GivenAnIndexSpillWhenThousandsOfChunksAreWrittenThenBuffersDoNotGrow) {
  // Given a writer with a spill, after 300 chunks
  MemorySpill spill;
  OneChannelWriter w(&spill);
  for (int i = 0; i < 300; ++i) w.chunk(100);
  const uint64_t held = w.writer.buffer_bytes();
  // When 5000 more chunks are written
  for (int i = 0; i < 5000; ++i) w.chunk(100);
  // Then the writer holds exactly the same buffers; the indexes went to the spill
  EXPECT_EQ(w.writer.buffer_bytes(), held);
  EXPECT_GT(spill.size(), 5000u * 50);
  ASSERT_TRUE(w.writer.close().ok());
  EXPECT_EQ(testing::read_all(w.sink.bytes()).size(), 5300u);
}

TEST(WriterMemory, GivenNoSpillWhenThousandsOfChunksAreWrittenThenTheIndexStaysInMemory) {
  // Given a writer without a spill (the in-memory index the test above must not see)
  OneChannelWriter w(nullptr);
  for (int i = 0; i < 300; ++i) w.chunk(100);
  const uint64_t held = w.writer.buffer_bytes();
  // When 5000 more chunks are written, Then the held index grows by at least 50 bytes a chunk
  for (int i = 0; i < 5000; ++i) w.chunk(100);
  EXPECT_GE(w.writer.buffer_bytes(), held + 5000u * 50);
}

TEST(WriterMemory, GivenChunksStartingWithEverLargerMessagesWhenWrittenThenNoBufferIsReallocated) {
  // Given an open writer (buffers sized for a full chunk)
  MemorySpill spill;
  OneChannelWriter w(&spill);
  const uint64_t held = w.writer.buffer_bytes();
  // When each chunk starts with a larger message than the last, up to the chunk size
  for (size_t size = 16; size <= 1024; size += 16) w.chunk(size);
  // Then no buffer was resized (before: one reallocation per new largest first message)
  EXPECT_EQ(w.writer.buffer_bytes(), held);
}

TEST(WriterMemory, GivenASpillThatFailsWhenIndexesAreSpilledThenTheWriterStopsNamingIt) {
  // Given a writer whose spill cannot be written
  FullSpill spill;
  OneChannelWriter w(&spill);
  // When chunks are written until their indexes fill a block
  Status st;
  for (int i = 0; i < 5000 && st.ok(); ++i) {
    const std::vector<uint8_t> data(10, 1);
    st = w.writer.write({w.channel, 0, 1000u + i, 1000u + i, data});
    if (st.ok()) st = w.writer.flush_chunk();
  }
  // Then the writer stops with an error naming the spill and the cause
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().find("spilling chunk indexes failed: no space left"), std::string::npos)
      << st.error();
  EXPECT_FALSE(w.writer.status().ok());
  EXPECT_FALSE(w.writer.close().ok());
}

TEST(WriterMemory, GivenASpillThatAlreadyHoldsBytesWhenUsedThenOnlyTheWritersOwnAreRead) {
  // Given a spill holding 1000 unrelated bytes before the writer starts
  MemorySpill spill;
  const std::vector<uint8_t> junk(1000, 0xAB);
  ASSERT_TRUE(spill.write(junk).ok());
  // When a file with spilled indexes is written
  const auto spilled = testing::make_recording(tiny_chunk_params(), 2, 8000, 200, 3, &spill);
  const auto in_memory = testing::make_recording(tiny_chunk_params(), 2, 8000, 200, 3);
  // Then it is the same file as without a spill
  EXPECT_GT(spill.size(), junk.size() + McapWriter::kIndexBlockBytes);
  EXPECT_EQ(spilled.bytes, in_memory.bytes);
}

}  // namespace
}  // namespace stereoball::recorder
