#include "recorder/io/file_io.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>

#include "recorder/core/reader.hpp"
#include "recorder/core/writer.hpp"

namespace stereoball::recorder {
namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("sb_recorder_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

TEST(FileIo, GivenAFileWrittenThroughFileSinkWhenReadThroughFileSourceThenMessagesMatch) {
  const auto path = temp_path("roundtrip.mcap");
  {
    auto sink = FileSink::create(path);
    ASSERT_TRUE(sink) << sink.error();
    McapWriter writer(WriterParams{});
    ASSERT_TRUE(writer.open(**sink).ok());
    const auto schema = writer.add_schema("S", "omgidl", std::string_view("struct S {};"));
    const auto channel = writer.add_channel(schema.value(), "a/b", "cdr");
    for (uint32_t i = 0; i < 100; ++i) {
      std::vector<uint8_t> data(i * 10, static_cast<uint8_t>(i));
      ASSERT_TRUE(writer.write({channel.value(), i, 1000u + i, 900u + i, data}).ok());
    }
    ASSERT_TRUE(writer.close().ok());
  }
  auto source = FileSource::open(path);
  ASSERT_TRUE(source) << source.error();
  McapReader reader(**source);
  ASSERT_TRUE(reader.open().ok());
  EXPECT_TRUE(reader.summary().complete);
  uint32_t n = 0;
  ASSERT_TRUE(reader
                  .for_each_message([&](const MessageView& m) {
                    EXPECT_EQ(m.sequence, n);
                    EXPECT_EQ(m.data.size(), n * 10);
                    EXPECT_EQ(m.publish_time_ns, 900u + n);
                    ++n;
                    return true;
                  })
                  .ok());
  EXPECT_EQ(n, 100u);
  std::filesystem::remove(path);
}

TEST(FileIo, GivenMissingPathsWhenOpenedThenTheErrorNamesThePath) {
  auto source = FileSource::open("/nonexistent/dir/x.mcap");
  ASSERT_FALSE(source);
  EXPECT_NE(source.error().find("/nonexistent/dir/x.mcap"), std::string::npos);
  auto sink = FileSink::create("/nonexistent/dir/y.mcap");
  ASSERT_FALSE(sink);
  EXPECT_NE(sink.error().find("/nonexistent/dir/y.mcap"), std::string::npos);
  auto dir = FileSource::open(std::filesystem::temp_directory_path().string());
  ASSERT_FALSE(dir);
  EXPECT_NE(dir.error().find("not a regular file"), std::string::npos);
}

TEST(FileIo, GivenASourceWhenReadingPastTheEndThenAnErrorIsReturned) {
  const auto path = temp_path("short.bin");
  {
    auto sink = FileSink::create(path);
    ASSERT_TRUE(sink);
    const std::vector<uint8_t> bytes = {1, 2, 3};
    ASSERT_TRUE((*sink)->write(bytes).ok());
  }
  auto source = FileSource::open(path);
  ASSERT_TRUE(source);
  EXPECT_EQ((*source)->size(), 3u);
  std::vector<uint8_t> out(4);
  EXPECT_FALSE((*source)->read(0, out).ok());
  out.resize(2);
  EXPECT_TRUE((*source)->read(1, out).ok());
  EXPECT_EQ(out[0], 2);
  std::filesystem::remove(path);
}

TEST(FileIo, GivenAFileSpillWhenWrittenThenItReadsBackAndLeavesNoFileBehind) {
  // Given an empty directory and a spill in it
  const auto dir = temp_path("spill_dir");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  auto spill = FileSpill::create(dir);
  ASSERT_TRUE(spill) << spill.error();
  // When bytes are written in pieces
  std::vector<uint8_t> a(70'000), b(5);
  for (size_t i = 0; i < a.size(); ++i) a[i] = static_cast<uint8_t>(i * 7);
  for (size_t i = 0; i < b.size(); ++i) b[i] = static_cast<uint8_t>(200 + i);
  ASSERT_TRUE((*spill)->write(a).ok());
  ASSERT_TRUE((*spill)->write(b).ok());
  // Then they read back at any offset, a read past the end is refused with a clear error
  EXPECT_EQ((*spill)->size(), a.size() + b.size());
  std::vector<uint8_t> got(10);
  ASSERT_TRUE((*spill)->read(a.size() - 5, got).ok());
  EXPECT_TRUE(std::equal(a.end() - 5, a.end(), got.begin()));
  EXPECT_TRUE(std::equal(b.begin(), b.end(), got.begin() + 5));
  const auto past = (*spill)->read(a.size(), got);
  ASSERT_FALSE(past.ok());
  EXPECT_NE(past.error().find("read past"), std::string::npos) << past.error();
  // And the directory shows no file at any time (the spill has no name)
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  spill->reset();
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  std::filesystem::remove_all(dir);
}

TEST(FileIo, GivenAMissingDirectoryWhenASpillIsCreatedThenTheErrorNamesIt) {
  const auto spill = FileSpill::create("/nonexistent/sb_spill");
  ASSERT_FALSE(spill);
  EXPECT_NE(spill.error().find("'/nonexistent/sb_spill'"), std::string::npos) << spill.error();
}

}  // namespace
}  // namespace stereoball::recorder
