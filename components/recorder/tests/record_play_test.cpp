// Integration tests of stereoball-record / -play / -info: real processes on a private DDS
// domain and a partition per test.

#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <thread>

#include "common/dds/serialized.hpp"
#include "common/dds/waitset.hpp"
#include "common/dds/writer.hpp"
#include "common/node/node_runner.hpp"
#include "process.hpp"
#include "recorder/core/reader.hpp"
#include "recorder/core/writer.hpp"
#include "recorder/io/file_io.hpp"
#include "stereoball/idl_text.hpp"

namespace sb = stereoball;
namespace rec = stereoball::recorder;
using namespace std::chrono_literals;
using sb::testing::Process;

namespace {

std::vector<std::string> domain_flags(const std::string& partition) {
  return {"--domain", std::to_string(sb::testing::test_domain()), "--partition", partition};
}

std::vector<std::string> args(std::vector<std::string> a, const std::string& partition) {
  for (auto& f : domain_flags(partition)) a.push_back(f);
  return a;
}

// Reads every message of a recording; complete/notes reported through the pointers.
std::vector<std::pair<uint64_t, uint64_t>> times_of(const std::string& path,
                                                    std::vector<std::vector<uint8_t>>* data,
                                                    rec::FileSummary* summary = nullptr) {
  auto source = rec::FileSource::open(path);
  EXPECT_TRUE(source) << source.error();
  if (!source) return {};
  rec::McapReader reader(**source);
  EXPECT_TRUE(reader.open().ok());
  std::vector<std::pair<uint64_t, uint64_t>> out;
  reader.for_each_message([&](const rec::MessageView& m) {
    out.emplace_back(m.log_time_ns, m.publish_time_ns);
    if (data) data->emplace_back(m.data.begin(), m.data.end());
    return true;
  });
  if (summary) *summary = reader.summary();
  return out;
}

uint64_t seq_of(const std::vector<uint8_t>& cdr) {
  uint64_t seq = 0;
  std::memcpy(&seq, cdr.data() + 4, 8);  // VelocityCommand.seq: first field after the header
  return seq;
}

void publish_commands(const std::string& partition, int count, int64_t period_ns) {
  sb::dds::DomainParticipant participant({sb::testing::test_domain(), partition});
  // The commands' own history is one deep (only the latest matters to a base): a command not
  // yet acknowledged when the next is written is replaced, and a sanitised recorder sharing a
  // loaded machine then misses it. These tests are about what the recorder does with what it
  // receives, so the writer keeps them all.
  sb::topics::QosSpec qos = sb::topics::kVelocityCommand.spec.qos;
  qos.history_depth = count;
  sb::dds::DataWriter<stereoball_msg_VelocityCommand> writer(participant,
                                                             sb::topics::kVelocityCommand, qos);
  ASSERT_TRUE(writer.wait_for_readers(1, 10'000'000'000));
  char source[] = "test";
  for (int i = 0; i < count; ++i) {
    stereoball_msg_VelocityCommand cmd{};
    cmd.seq = static_cast<uint64_t>(i);
    cmd.stamp_ns = sb::node::now_ns();
    cmd.linear_mps = 0.1 * i;
    cmd.source = source;
    writer.write(cmd);
    std::this_thread::sleep_for(std::chrono::nanoseconds(period_ns));
  }
  // Every command reached the recorder before the writer goes away (else the last ones may
  // still be in flight when the test inspects the file)
  ASSERT_TRUE(writer.wait_for_acks(10'000'000'000));
}

// Messages readable in the file at path now (0 when it cannot be opened yet); no test
// expectations, for polling a file that is still being written.
size_t messages_in(const std::string& path) {
  auto source = rec::FileSource::open(path);
  if (!source) return 0;
  rec::McapReader reader(**source);
  if (!reader.open().ok()) return 0;
  size_t n = 0;
  reader.for_each_message([&](const rec::MessageView&) {
    ++n;
    return true;
  });
  return n;
}

TEST(RecordPlay, GivenPublishedCommandsWhenRecordedAndInterruptedThenTheFileHoldsThemAll) {
  const auto partition = sb::testing::unique_partition();
  const auto file = sb::testing::temp_dir() + "/rec.mcap";
  auto recorder = Process::start(
      args({sb::testing::bin("stereoball-record"), "cmd/velocity", "-o", file, "-q"}, partition));
  ASSERT_TRUE(recorder.wait_for_output("recording 1 topic", 10s)) << recorder.output();
  const int64_t before = sb::node::now_ns();
  publish_commands(partition, 100, 5'000'000);
  const int64_t after = sb::node::now_ns();
  std::this_thread::sleep_for(300ms);
  recorder.signal(SIGINT);
  ASSERT_EQ(recorder.wait_for_exit(10s), 0) << recorder.output();
  EXPECT_NE(recorder.output().find("100 messages written, 0 dropped, 0 lost"), std::string::npos)
      << recorder.output();

  std::vector<std::vector<uint8_t>> data;
  rec::FileSummary summary;
  const auto times = times_of(file, &data, &summary);
  EXPECT_TRUE(summary.complete);
  ASSERT_EQ(times.size(), 100u);
  for (size_t i = 0; i < data.size(); ++i) {
    EXPECT_EQ(seq_of(data[i]), i);
    EXPECT_GE(times[i].second, static_cast<uint64_t>(before));  // publish = source stamp
    EXPECT_LE(times[i].second, times[i].first);                 // received after sent
    EXPECT_LE(times[i].first, static_cast<uint64_t>(after) + 1'000'000'000);
  }
  const auto& schema = summary.schemas.begin()->second;
  EXPECT_EQ(schema.name, "stereoball::msg::VelocityCommand");
  EXPECT_EQ(schema.encoding, "omgidl");
  EXPECT_EQ(std::string(schema.data.begin(), schema.data.end()), sb::idl_text());
  EXPECT_EQ(summary.channels.begin()->second.message_encoding, "cdr");
}

TEST(RecordPlay, GivenAKilledRecorderWhenInspectedThenInfoSaysIncompleteAndMessagesSurvive) {
  const auto partition = sb::testing::unique_partition();
  const auto file = sb::testing::temp_dir() + "/killed.mcap";
  auto recorder = Process::start(args({sb::testing::bin("stereoball-record"), "cmd/velocity", "-o",
                                       file, "-q", "--flush-period", "0.2"},
                                      partition));
  ASSERT_TRUE(recorder.wait_for_output("recording 1 topic", 10s)) << recorder.output();
  publish_commands(partition, 50, 2'000'000);
  // Wait until the periodic flush has put all 50 on disk (a deadline, not a fixed sleep: a
  // loaded or sanitised host flushes later), then kill the recorder without warning
  const auto end = std::chrono::steady_clock::now() + 10s;
  while (messages_in(file) < 50u && std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(50ms);
  }
  ASSERT_EQ(messages_in(file), 50u) << "not flushed within 10 s" << recorder.output();
  recorder.signal(SIGKILL);
  recorder.wait_for_exit(5s);
  const auto [code, out] = sb::testing::run({sb::testing::bin("stereoball-info"), file}, 10s);
  EXPECT_EQ(code, 0) << out;
  EXPECT_NE(out.find("complete:  NO"), std::string::npos) << out;
  EXPECT_NE(out.find("no summary, scanned linearly"), std::string::npos) << out;
  std::vector<std::vector<uint8_t>> data;
  EXPECT_EQ(times_of(file, &data).size(), 50u);
}

// Hand-made CDR of a VelocityCommand (XCDR1 little endian).
std::vector<uint8_t> command_cdr(uint64_t seq) {
  std::vector<uint8_t> b = {0x00, 0x01, 0x00, 0x00};  // XCDR1 little endian
  // XCDR1 aligns each primitive to its size, counted from the end of the 4-byte header.
  auto put = [&](const void* p, size_t n, size_t align) {
    while ((b.size() - 4) % align != 0) b.push_back(0);
    const auto* c = static_cast<const uint8_t*>(p);
    b.insert(b.end(), c, c + n);
  };
  const int64_t stamp = 42, capture_stamp = 40;
  const double lin = 0.5, ang = -0.25;
  const uint32_t len = 5;
  put(&seq, 8, 8);
  put(&stamp, 8, 8);
  put(&capture_stamp, 8, 8);
  put(&lin, 8, 8);
  put(&ang, 8, 8);
  put(&len, 4, 4);
  put("play", 5, 1);
  // AuthTag of an unsigned (keyless) sample: key_id 0, link id, stamp, zero MAC.
  const uint32_t key_id = 0;
  const uint64_t link_id = 7;
  const int64_t auth_stamp = 1'700'000'000'000'000'000 + static_cast<int64_t>(seq);
  const uint8_t mac[32] = {};
  put(&key_id, 4, 4);
  put(&link_id, 8, 8);
  put(&auth_stamp, 8, 8);
  put(mac, sizeof mac, 1);
  return b;
}

// Writes a recording of count commands with irregular gaps; returns the log times.
std::vector<uint64_t> write_recording(const std::string& path, int count) {
  auto sink = rec::FileSink::create(path);
  EXPECT_TRUE(sink);
  rec::McapWriter writer(rec::WriterParams{});
  EXPECT_TRUE(writer.open(**sink).ok());
  const auto schema =
      writer.add_schema("stereoball::msg::VelocityCommand", "omgidl", sb::idl_text());
  const auto channel = writer.add_channel(schema.value(), "cmd/velocity", "cdr");
  std::vector<uint64_t> times;
  uint64_t t = 1'700'000'000'000'000'000ull;
  for (int i = 0; i < count; ++i) {
    t += (5 + (i * 7) % 26) * 1'000'000ull;  // 5..30 ms gaps
    times.push_back(t);
    const auto cdr = command_cdr(static_cast<uint64_t>(i));
    EXPECT_TRUE(writer.write({channel.value(), static_cast<uint32_t>(i), t, t, cdr}).ok());
  }
  EXPECT_TRUE(writer.close().ok());
  return times;
}

// Plays path with extra flags and returns (seq, publish time ns) of every sample.
std::vector<std::pair<uint64_t, int64_t>> play_and_receive(const std::string& path,
                                                           std::vector<std::string> extra,
                                                           size_t expect) {
  const auto partition = sb::testing::unique_partition() + std::to_string(expect);
  sb::dds::DomainParticipant participant({sb::testing::test_domain(), partition});
  // Deeper history than the table's keep-last-1, so the test sees every sample it is sent.
  auto qos = sb::topics::kVelocityCommand.spec.qos;
  qos.history_depth = 256;
  qos.deadline_ns = 0;
  sb::dds::SerializedReader reader(participant, sb::topics::kVelocityCommand.spec, qos);
  std::vector<std::string> a = {sb::testing::bin("stereoball-play"), path, "--wait", "1.5"};
  a.insert(a.end(), extra.begin(), extra.end());
  auto player = Process::start(args(a, partition));
  sb::dds::WaitSet waitset(participant);
  waitset.attach(reader.handle(), 1);
  std::vector<std::pair<uint64_t, int64_t>> got;
  const int64_t deadline = sb::node::monotonic_ns() + 20'000'000'000;
  std::vector<sb::dds::SerializedSample> samples;
  while (got.size() < expect && sb::node::monotonic_ns() < deadline) {
    waitset.wait(100'000'000);
    samples.clear();
    reader.take(samples, 64);
    // The writer's source timestamp is when the player published: what its timing is about,
    // without this test's own wake-up latency.
    for (const auto& s : samples) got.emplace_back(seq_of(s.cdr), s.source_stamp_ns);
  }
  EXPECT_EQ(player.wait_for_exit(10s), 0) << player.output();
  return got;
}

// Span of the played messages over the span they should take (1 = exact timing).
double span_ratio(const std::vector<uint64_t>& log_times,
                  const std::vector<std::pair<uint64_t, int64_t>>& got, double rate) {
  const double want = (log_times[got.back().first] - log_times[got.front().first]) / rate;
  return static_cast<double>(got.back().second - got.front().second) / want;
}

double median_gap_error_ms(const std::vector<uint64_t>& log_times,
                           const std::vector<std::pair<uint64_t, int64_t>>& got, double rate) {
  std::vector<double> errors;
  for (size_t i = 1; i < got.size(); ++i) {
    const double want = (log_times[got[i].first] - log_times[got[i - 1].first]) / rate;
    const double seen = static_cast<double>(got[i].second - got[i - 1].second);
    errors.push_back(std::abs(seen - want) / 1e6);
  }
  std::sort(errors.begin(), errors.end());
  return errors.empty() ? 1e9 : errors[errors.size() / 2];
}

TEST(RecordPlay, GivenARecordingWhenPlayedAtRateOneThenInterMessageTimingIsKept) {
  const auto file = sb::testing::temp_dir() + "/play.mcap";
  const auto times = write_recording(file, 60);
  const auto got = play_and_receive(file, {}, times.size());
  ASSERT_EQ(got.size(), times.size());
  for (size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i].first, i);
  // The schedule is absolute (no drift), so the whole span holds even on a loaded machine; the
  // per-gap error depends on scheduling and is printed as a figure, not asserted.
  EXPECT_NEAR(span_ratio(times, got, 1.0), 1.0, 0.1);
  std::printf("play rate 1: median inter-message timing error %.3f ms over %zu gaps\n",
              median_gap_error_ms(times, got, 1.0), got.size() - 1);
}

TEST(RecordPlay, GivenARateAndAStartOffsetWhenPlayedThenGapsScaleAndTheStartIsSkipped) {
  const auto file = sb::testing::temp_dir() + "/fast.mcap";
  const auto times = write_recording(file, 60);
  // Offset that falls just after message 20.
  const double offset_s = (times[20] - times[0]) / 1e9 + 1e-4;
  const auto got = play_and_receive(
      file, {"--rate", "2", "--start-offset", std::to_string(offset_s)}, times.size() - 21);
  ASSERT_EQ(got.size(), times.size() - 21);
  EXPECT_EQ(got.front().first, 21u);
  EXPECT_NEAR(span_ratio(times, got, 2.0), 1.0, 0.1);
  std::printf("play rate 2: median inter-message timing error %.3f ms\n",
              median_gap_error_ms(times, got, 2.0));
}

// A closed recording of ball/track samples (payloads are not valid CDR: they are never
// published, every chunk's size claim is rewritten to 3 GiB so none can be read).
std::string unreadable_recording(const std::string& dir) {
  rec::WriterParams params;
  params.chunk_size_bytes = 2048;
  rec::MemorySink sink;
  rec::McapWriter writer(params);
  EXPECT_TRUE(writer.open(sink).ok());
  const auto schema = writer.add_schema("stereoball::msg::BallTrack", "omgidl", "struct X {};");
  const auto channel = writer.add_channel(schema.value(), "ball/track", "cdr").value();
  const std::vector<uint8_t> payload(300, 7);
  for (uint32_t i = 0; i < 40; ++i) {
    EXPECT_TRUE(writer.write({channel, i, 1'000'000'000ull + i * 1'000'000ull, 0, payload}).ok());
  }
  EXPECT_TRUE(writer.close().ok());
  std::vector<uint8_t> bytes = sink.bytes();
  rec::MemorySource source(bytes);
  rec::McapReader reader(source);
  EXPECT_TRUE(reader.open().ok());
  const auto indexes = reader.chunk_indexes();
  for (const auto& index : indexes) {
    const uint64_t field = index.chunk_start_offset + rec::kRecordPrefixBytes + 16;
    for (int b = 0; b < 8; ++b)
      bytes[field + b] = static_cast<uint8_t>((uint64_t{3} << 30) >> (8 * b));
  }
  const std::string path = dir + "/unreadable.mcap";
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  return path;
}

// Issue 22: info and play said "complete: yes" and exited 0 with 0 messages readable.
TEST(RecordPlay, GivenAFileOfWhichNothingCanBeReadWhenToolsRunThenTheyFailClearly) {
  const auto dir = sb::testing::temp_dir();
  const std::string path = unreadable_recording(dir);
  const auto started = std::chrono::steady_clock::now();
  auto [code, out] = sb::testing::run({sb::testing::bin("stereoball-info"), path}, 10s);
  const double info_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  std::printf(
      "[figure] stereoball info on chunks claiming 3 GiB: %.1f ms (process start "
      "included)\n",
      info_ms);
  EXPECT_EQ(code, 1) << out;
  EXPECT_NE(out.find("no message could be read"), std::string::npos) << out;
  EXPECT_NE(out.find("more than the reader's limit"), std::string::npos) << out;
  EXPECT_EQ(out.find("complete:  yes"), std::string::npos) << out;
  std::tie(code, out) =
      sb::testing::run(args({sb::testing::bin("stereoball-play"), path, "--wait", "0"},
                            sb::testing::unique_partition()),
                       20s);
  EXPECT_EQ(code, 1) << out;
  EXPECT_NE(out.find("no message could be read"), std::string::npos) << out;
}

TEST(RecordPlay, GivenBadInputsWhenToolsRunThenOneClearErrorAndNonZeroExit) {
  const auto dir = sb::testing::temp_dir();
  std::ofstream(dir + "/text.mcap") << "just some text\n";
  auto [code, out] =
      sb::testing::run({sb::testing::bin("stereoball-play"), dir + "/text.mcap"}, 10s);
  EXPECT_NE(code, 0);
  EXPECT_NE(out.find("not an MCAP file: bad magic"), std::string::npos) << out;
  std::tie(code, out) = sb::testing::run({sb::testing::bin("stereoball-info"), dir + "/none"}, 10s);
  EXPECT_NE(code, 0);
  EXPECT_NE(out.find("cannot open"), std::string::npos) << out;
  std::tie(code, out) = sb::testing::run({sb::testing::bin("stereoball-record"), "ball/trak"}, 10s);
  EXPECT_NE(code, 0);
  EXPECT_NE(out.find("unknown topic 'ball/trak'"), std::string::npos) << out;
  std::tie(code, out) = sb::testing::run(
      {sb::testing::bin("stereoball-play"), dir + "/text.mcap", "--rate", "0"}, 10s);
  EXPECT_NE(code, 0);
  EXPECT_NE(out.find("rate"), std::string::npos) << out;
}

}  // namespace
