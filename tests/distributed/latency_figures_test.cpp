// The latency figures of stereoball bench latency, on observer logs written by hand.

#include "latency_figures.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <string>

namespace stereoball::distributed {
namespace {

constexpr std::int64_t kT0 = 1'733'000'000'000'000'000;
constexpr std::int64_t kPeriod = 33'333'333;  // 30 Hz
constexpr std::int64_t kMs = 1'000'000;

// Frame i exposed at kT0 + i * kPeriod: taken by the detector 3 ms later, detection published
// after 4 ms of processing, track 1 ms later, command 0.5 ms after that.
void add_frame(ObserverLog& log, int i) {
  const std::int64_t capture = kT0 + i * kPeriod;
  log.detections.push_back(
      {capture + 8 * kMs, capture, capture + 7 * kMs, static_cast<std::uint64_t>(i), 0, 4.0});
  log.tracks.push_back(
      {capture + 9 * kMs, capture, capture + 8 * kMs, static_cast<std::uint64_t>(i), 1, 1.0, 0.0});
  log.commands.push_back({capture + 9 * kMs, capture + 8 * kMs + kMs / 2,
                          static_cast<std::uint64_t>(2 * i), 0.1, 0.0, capture});
  // A minimum-rate command in between answers no track
  log.commands.push_back(
      {capture + 20 * kMs, capture + 20 * kMs, static_cast<std::uint64_t>(2 * i + 1), 0.1, 0.0, 0});
}

TEST(LatencyFigures, GivenFramesThroughEveryStage_ThenEachStageAndEndToEnd) {
  // Given 30 frames, frames 10 and 11 lost before detection
  ObserverLog log;
  for (int i = 0; i < 30; ++i) {
    if (i != 10 && i != 11) add_frame(log, i);
  }
  // When the figures of all of them are taken
  const LatencyFigures f = latency_figures(log, log, kT0, kT0 + 30 * kPeriod, 30.0);
  // Then every stage has its duration and the end to end is their sum, from the exposure
  EXPECT_NEAR(f.frame_received.p50, 3.0, 1e-9);
  EXPECT_NEAR(f.detection.p99, 4.0, 1e-9);
  EXPECT_NEAR(f.track.max, 1.0, 1e-9);
  EXPECT_NEAR(f.command.p90, 0.5, 1e-9);
  EXPECT_NEAR(f.end_to_end.p50, 8.5, 1e-9);
  EXPECT_EQ(f.end_to_end.n, 28u);
  // And the two lost frames are counted, timer commands are not answers
  EXPECT_EQ(f.frames_expected, 30u);
  EXPECT_EQ(f.frames_lost, 2u);
  EXPECT_EQ(f.tracks_unanswered, 0u);
}

TEST(LatencyFigures, GivenWindowAndAnUnansweredTrack_ThenOnlyWindowFramesAndTheMissingAnswer) {
  // Given 10 frames, the command of frame 5 missing
  ObserverLog log;
  for (int i = 0; i < 10; ++i) add_frame(log, i);
  log.commands.erase(log.commands.begin() + 10);
  // When only frames 2..7 are in the window
  const LatencyFigures f = latency_figures(log, log, kT0 + 2 * kPeriod, kT0 + 8 * kPeriod, 30.0);
  // Then six frames count, one track went unanswered
  EXPECT_EQ(f.detection.n, 6u);
  EXPECT_EQ(f.end_to_end.n, 5u);
  EXPECT_EQ(f.tracks_unanswered, 1u);
  EXPECT_EQ(f.frames_lost, 0u);
}

TEST(LatencyFigures, GivenFrames_ThenEachFramesStagesAndACsvLinePerFrame) {
  // Given 4 frames, frame 2 without a command answering its track
  ObserverLog log;
  for (int i = 0; i < 4; ++i) add_frame(log, i);
  log.commands.erase(log.commands.begin() + 4);
  // When their stages are taken, the window starting at frame 1
  const auto frames = frame_stages(log, log, kT0, kT0 + 4 * kPeriod);
  // Then each frame has its stages, the unanswered one no command and no end to end
  ASSERT_EQ(frames.size(), 4u);
  EXPECT_EQ(frames[1].seq, 1u);
  EXPECT_NEAR(frames[1].received_ms, 3.0, 1e-9);
  EXPECT_NEAR(frames[1].end_to_end_ms, 8.5, 1e-9);
  EXPECT_EQ(frames[2].track_state, 1);
  EXPECT_LT(frames[2].command_ms, 0.0);
  EXPECT_LT(frames[2].end_to_end_ms, 0.0);
  // And the CSV has a header and one line per frame, frame 0 outside the measured window
  const std::string csv = to_csv(frames, kT0 + kPeriod);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5);
  EXPECT_EQ(csv.substr(0, csv.find(',')), "capture_ns");
  const std::string first = csv.substr(csv.find('\n') + 1);
  EXPECT_EQ(first.substr(first.find('\n') - 2, 2), ",0");
  EXPECT_NE(csv.find(",8.500,1\n"), std::string::npos);
}

TEST(LatencyFigures, GivenOneSlowLostBallFrame_ThenItIsTheSlowestShareWithItsStages) {
  // Given 100 answered frames, frame 50 without a ball found and 20 ms slower in detection
  ObserverLog log;
  for (int i = 0; i < 100; ++i) add_frame(log, i);
  log.detections[50].status = 1;
  log.detections[50].processing_ms = 24.0;
  log.detections[50].publish_ns += 20 * kMs;
  log.tracks[50].publish_ns += 20 * kMs;
  log.commands[100].stamp_ns += 20 * kMs;
  const auto frames = frame_stages(log, log, kT0, kT0 + 100 * kPeriod);
  // When the slowest 1 % are taken (frame 0 before the window)
  const SlowFrames slow = slowest_frames(frames, kT0 + kPeriod, 1.0);
  // Then it is that frame alone, with its stages
  EXPECT_EQ(slow.n, 1u);
  EXPECT_EQ(slow.not_found, 1u);
  EXPECT_NEAR(slow.detection_ms, 24.0, 1e-6);
  EXPECT_NEAR(slow.received_ms, 3.0, 1e-6);
  EXPECT_NEAR(slow.end_to_end_ms, 28.5, 1e-6);
  EXPECT_NE(to_text(slow, 1.0).find("1 frames, 1 without a ball found"), std::string::npos);
  EXPECT_EQ(to_json(slow)["not_found"], 1);
  // And with no answered frame in the window, nothing
  EXPECT_EQ(slowest_frames(frames, kT0 + 200 * kPeriod, 1.0).n, 0u);
}

TEST(LatencyFigures, GivenFigures_ThenJsonHasEveryQuantileFinite) {
  ObserverLog log;
  for (int i = 0; i < 5; ++i) add_frame(log, i);
  const auto j = to_json(latency_figures(log, log, kT0, kT0 + 5 * kPeriod, 30.0), CoreLoad{});
  for (const char* stage :
       {"frame_received_ms", "detection_ms", "track_ms", "command_ms", "end_to_end_ms"}) {
    for (const char* q : {"p50", "p90", "p99", "max"}) {
      ASSERT_TRUE(j.at(stage).at(q).is_number()) << stage << q;
      EXPECT_TRUE(std::isfinite(j.at(stage).at(q).get<double>())) << stage << q;
    }
  }
  EXPECT_NEAR(j["end_to_end_ms"]["max"].get<double>(), 8.5, 1e-9);
}

TEST(ProgramCpu, GivenTwoSamples_ThenEachProgramsCpuAndRunQueueWaitPerFrame) {
  // Given a detector with a thread alive at both samples and one started in between, and a
  // tracker whose only thread ended in between (its ticks still count every thread)
  ProgramSample start, end;
  start["ball_detector"].threads[{10, 10}] = {100 * kMs, 5 * kMs};
  start["ball_detector"].ticks = 10;
  end["ball_detector"].threads[{10, 10}] = {400 * kMs, 35 * kMs};
  end["ball_detector"].threads[{10, 12}] = {100 * kMs, 10 * kMs};
  end["ball_detector"].ticks = 50;
  start["tracker"].threads[{20, 21}] = {10 * kMs, 1 * kMs};
  start["tracker"].ticks = 1;
  end["tracker"].ticks = 3;
  // When their use over 100 frame periods is taken
  const auto cpu = program_cpu(start, end, 100.0);
  // Then the detector used 300 + 100 ms of CPU and waited 30 + 10 ms for a core: 4 and 0.4 ms
  // per frame (its ticks, 10 ms steps, say the same); the tracker's CPU comes from its ticks
  const double ms_per_tick = 1e3 / static_cast<double>(sysconf(_SC_CLK_TCK));
  ASSERT_EQ(cpu.size(), 2u);
  EXPECT_NEAR(cpu.at("ball_detector").cpu_ms, std::max(4.0, 40 * ms_per_tick / 100), 1e-9);
  EXPECT_NEAR(cpu.at("ball_detector").runqueue_ms, 0.4, 1e-9);
  EXPECT_NEAR(cpu.at("tracker").cpu_ms, 2 * ms_per_tick / 100, 1e-9);
  EXPECT_NEAR(cpu.at("tracker").runqueue_ms, 0.0, 1e-9);
  // And the text and JSON name each program with both figures
  const std::string text = program_cpu_text(cpu);
  EXPECT_NE(text.find("ball_detector 4.00 (0.40)"), std::string::npos) << text;
  const auto j = program_cpu_json(cpu);
  EXPECT_NEAR(j.at("ball_detector").at("runqueue_wait_ms").get<double>(), 0.4, 1e-9);
  EXPECT_TRUE(j.at("tracker").at("cpu_ms").is_number());
}

TEST(ProgramCpu, GivenThisProcess_ThenItsProgramIsSampledWithItsThreads) {
  // Given this test process, when it is sampled, then it appears under its own program name
  // (its argv[0] as glibc kept it; grouped test executables share one) with at least one
  // thread (the counters the benchmark reads exist on this kernel)
  const auto sample = program_sample({static_cast<int>(getpid())});
  ASSERT_EQ(sample.size(), 1u);
  EXPECT_EQ(sample.begin()->first, std::string(program_invocation_short_name));
  EXPECT_FALSE(sample.begin()->second.threads.empty());
}

}  // namespace
}  // namespace stereoball::distributed
