#include "recorder/io/recording.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <thread>

#include "recorder/core/reader.hpp"

namespace stereoball::recorder {
namespace {

std::string temp_dir() {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("sb_recording_" + std::to_string(::getpid()) + "_" +
                    ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

std::vector<RecordedTopic> two_topics() {
  return {{"a/x", "t::A", "struct A {};"}, {"b/y", "t::B", "struct B {};"}};
}

// Reads every message of a file: (topic, payload, log time).
struct Read {
  std::string topic;
  std::vector<uint8_t> data;
  uint64_t log_ns;
};
std::vector<Read> read_file(const std::string& path, bool* complete = nullptr) {
  auto source = FileSource::open(path);
  EXPECT_TRUE(source) << source.error();
  if (!source) return {};
  McapReader reader(**source);
  EXPECT_TRUE(reader.open().ok());
  std::vector<Read> out;
  reader.for_each_message([&](const MessageView& m) {
    out.push_back({reader.summary().channels.at(m.channel_id).topic,
                   {m.data.begin(), m.data.end()},
                   m.log_time_ns});
    return true;
  });
  if (complete) *complete = reader.summary().complete;
  return out;
}

TEST(Recording, GivenPushesFromTwoThreadsWhenStoppedThenTheFileHoldsEveryMessage) {
  RecordingParams p;
  p.path = temp_dir() + "/r.mcap";
  auto rec = Recording::start(p, two_topics());
  ASSERT_TRUE(rec) << rec.error();
  auto producer = [&](size_t topic) {
    for (uint32_t i = 0; i < 500; ++i) {
      std::vector<uint8_t> cdr(100, static_cast<uint8_t>(i));
      ASSERT_TRUE((*rec)->push(topic, std::move(cdr), 1000 + i, 900 + i));
    }
  };
  std::thread t1(producer, 0), t2(producer, 1);
  t1.join();
  t2.join();
  ASSERT_TRUE((*rec)->stop().ok());
  const auto counters = (*rec)->counters();
  EXPECT_EQ(counters[0].messages, 500u);
  EXPECT_EQ(counters[1].messages, 500u);
  EXPECT_EQ(counters[0].dropped + counters[1].dropped, 0u);
  bool complete = false;
  const auto msgs = read_file(p.path, &complete);
  EXPECT_TRUE(complete);
  ASSERT_EQ(msgs.size(), 1000u);
  size_t on_a = 0;
  for (const auto& m : msgs) on_a += m.topic == "a/x";
  EXPECT_EQ(on_a, 500u);
}

TEST(Recording, GivenASizeLimitWhenRecordingThenSeveralCompleteFilesTogetherHoldEverything) {
  RecordingParams p;
  p.path = temp_dir() + "/split.mcap";
  p.split_size_bytes = 1 << 20;
  p.writer.chunk_size_bytes = 64 * 1024;
  p.writer.compression = Compression::kNone;
  auto rec = Recording::start(p, two_topics());
  ASSERT_TRUE(rec);
  for (uint32_t i = 0; i < 400; ++i) {
    while (!(*rec)->push(i % 2, std::vector<uint8_t>(10'000, 1), 1000 + i, 1000 + i)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  ASSERT_TRUE((*rec)->stop().ok());
  const auto files = (*rec)->files();
  ASSERT_GE(files.size(), 3u);
  EXPECT_NE(files[0].find("split_000.mcap"), std::string::npos);
  size_t total = 0;
  uint64_t last_log = 0;
  for (const auto& f : files) {
    bool complete = false;
    const auto msgs = read_file(f, &complete);
    EXPECT_TRUE(complete) << f;
    EXPECT_LT(std::filesystem::file_size(f), 2u << 20) << f;
    for (const auto& m : msgs) {
      EXPECT_GT(m.log_ns, last_log);  // files continue each other in order
      last_log = m.log_ns;
    }
    total += msgs.size();
  }
  EXPECT_EQ(total, 400u);
}

TEST(Recording, GivenADurationLimitWhenRecordingThenFilesSpanAtMostThatLong) {
  RecordingParams p;
  p.path = temp_dir() + "/timed.mcap";
  p.split_duration_ns = 1'000'000'000;
  auto rec = Recording::start(p, two_topics());
  ASSERT_TRUE(rec);
  for (uint64_t i = 0; i < 50; ++i) {  // 5 s of log time at 10 Hz
    ASSERT_TRUE((*rec)->push(0, {1, 2, 3}, 1'000'000'000 + i * 100'000'000, 0));
  }
  ASSERT_TRUE((*rec)->stop().ok());
  const auto files = (*rec)->files();
  ASSERT_EQ(files.size(), 5u);
  for (const auto& f : files) {
    const auto msgs = read_file(f);
    ASSERT_EQ(msgs.size(), 10u) << f;
    EXPECT_LT(msgs.back().log_ns - msgs.front().log_ns, 1'000'000'000u);
  }
}

TEST(Recording, GivenAFullQueueWhenPushingThenDropsAreCountedAndMemoryStaysBounded) {
  RecordingParams p;
  p.path = temp_dir() + "/bounded.mcap";
  p.queue_limit_bytes = 1 << 20;
  auto rec = Recording::start(p, two_topics());
  ASSERT_TRUE(rec);
  // Far faster than any disk: 2000 x 100 kB pushed in a tight loop.
  uint64_t refused = 0, max_queued = 0;
  for (uint32_t i = 0; i < 2000; ++i) {
    if (!(*rec)->push(1, std::vector<uint8_t>(100'000, 7), 1000 + i, 1000 + i)) ++refused;
    max_queued = std::max(max_queued, (*rec)->queued_bytes());
  }
  ASSERT_TRUE((*rec)->stop().ok());
  const auto c = (*rec)->counters();
  EXPECT_GT(refused, 0u);
  EXPECT_EQ(c[1].dropped, refused);
  EXPECT_EQ(c[1].messages + c[1].dropped, 2000u);
  EXPECT_LE(max_queued, p.queue_limit_bytes);
  EXPECT_EQ(read_file(p.path).size(), c[1].messages);
}

TEST(Recording, GivenThousandsOfChunksWhenRecordedThenTheIndexIsSpilledAndTheFileIsIndexed) {
  // Given a recording in 1 KiB chunks (each closes after a few messages)
  RecordingParams p;
  const auto dir = temp_dir();
  p.path = dir + "/r.mcap";
  p.writer.chunk_size_bytes = 1024;
  auto rec = Recording::start(p, two_topics());
  ASSERT_TRUE(rec) << rec.error();
  // When 8000 messages are recorded (2000 chunks, whose indexes fill several blocks)
  for (uint32_t i = 0; i < 8000; ++i) {
    std::vector<uint8_t> cdr(300, static_cast<uint8_t>(i));
    while (!(*rec)->push(i % 2, std::move(cdr), 1000 + i, 900 + i)) {
      cdr.assign(300, static_cast<uint8_t>(i));
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  ASSERT_TRUE((*rec)->stop().ok());
  // Then the file is complete and read through its index, every message in it
  auto source = FileSource::open(p.path);
  ASSERT_TRUE(source) << source.error();
  McapReader reader(**source);
  ASSERT_TRUE(reader.open().ok());
  EXPECT_TRUE(reader.summary().complete);
  EXPECT_TRUE(reader.summary().indexed);
  EXPECT_GE(reader.chunk_indexes().size(), 2000u);  // more if a 1 s flush came between
  EXPECT_EQ(reader.summary().statistics.message_count, 8000u);
  EXPECT_EQ(read_file(p.path).size(), 8000u);
  // And the directory holds the recording only (the spill left nothing)
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir),
                          std::filesystem::directory_iterator()),
            1);
}

TEST(Recording, GivenAnUnwritablePathOrBadParamsWhenStartingThenAClearError) {
  RecordingParams p;
  p.path = "/nonexistent/dir/r.mcap";
  auto rec = Recording::start(p, two_topics());
  ASSERT_FALSE(rec);
  EXPECT_NE(rec.error().find("/nonexistent/dir/r.mcap"), std::string::npos);
  p.path = temp_dir() + "/x.mcap";
  p.queue_limit_bytes = 10;
  rec = Recording::start(p, two_topics());
  ASSERT_FALSE(rec);
  EXPECT_NE(rec.error().find("queue_limit_bytes"), std::string::npos);
}

}  // namespace
}  // namespace stereoball::recorder
