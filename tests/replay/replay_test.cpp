// Replay tests (openpilot style): a generated recording of a short simulator run is played
// with stereoball-play into ONE node at a time (ball_detector, tracker, motion_controller);
// the node's outputs are captured and compared with committed references in
// tests/replay/reference/ within stated tolerances. SB_REGENERATE_REFERENCES=1 rewrites the
// references from the current outputs. SB_REPLAY_CONFIG_DIR runs the nodes with another
// config folder (e.g. to check that a changed parameter makes the tests fail).

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "process.hpp"
#include "replay_harness.hpp"
#include "replay_recording.hpp"
#include "stereoball/topics.hpp"

namespace sb = stereoball;
namespace st = stereoball::testing;
using json = nlohmann::json;
using sb::replay::NodeReplay;
using namespace std::chrono_literals;

namespace {

// Tolerances of the comparisons.
constexpr double kCentreTolPx = 0.5;       // detection circle centres and radii, pixels
constexpr double kPositionTolM = 0.01;     // 3D positions, metres
constexpr double kSsdTol = 1.0;            // block matching SSD (integer sums of bytes)
constexpr double kLinearTolMps = 0.01;     // settled linear command, m/s
constexpr double kAngularTolRadps = 0.01;  // settled angular command, rad/s
// Frames travel best effort keep-last-1: this share of the frames must be answered.
constexpr double kMinFrameCoverage = 0.5;

class ReplayTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::string(st::temp_dir());
    const std::string path = *dir_ + "/replay.mcap";
    const auto error =
        sb::replay::make_replay_recording(path, st::test_domain(), st::unique_partition() + "_gen");
    ASSERT_TRUE(error.ok()) << error.error();
    recording_ = new std::string(path);
  }
  static void TearDownTestSuite() {
    std::error_code ec;  // the recording is ~80 MB: never leave it behind
    if (dir_) std::filesystem::remove_all(*dir_, ec);
    delete recording_;
    delete dir_;
    recording_ = nullptr;
  }

  void SetUp() override { ASSERT_NE(recording_, nullptr) << "the recording was not generated"; }

  static std::string* recording_;
  static std::string* dir_;
};

std::string* ReplayTest::recording_ = nullptr;
std::string* ReplayTest::dir_ = nullptr;

json circle(const stereoball_msg_EyeCircle& c) {
  return {c.x_px, c.y_px, c.radius_px};
}

json vec3(const double* v) {
  return {v[0], v[1], v[2]};
}

// The compared fields of one detection (keyed by "seq", the frame it answers).
json detection_row(const stereoball_msg_BallDetection& d) {
  return {{"seq", d.frame_seq},
          {"status", static_cast<int>(d.status)},
          {"left", circle(d.left)},
          {"right", circle(d.right)},
          {"position_m", vec3(d.position_m)}};
}

// The compared fields of one track (keyed by "seq", the frame it answers).
json track_row(const stereoball_msg_BallTrack& t) {
  return {{"seq", t.frame_seq},
          {"state", static_cast<int>(t.state)},
          {"verdict", static_cast<int>(t.verdict)},
          {"position_valid", t.position_valid},
          {"position_m", vec3(t.position_m)},
          {"last_seen_side", static_cast<int>(t.last_seen_side)},
          {"ssd", t.ssd}};
}

TEST_F(ReplayTest, BallDetectorFramesToDetectionsMatchTheReference) {
  // Given the ball_detector node and a reader of its detections
  NodeReplay<stereoball_msg_BallDetection> replay(*recording_, sb::topics::kBallDetection);
  ASSERT_NO_FATAL_FAILURE(replay.start_node("ball_detector", "ball_detector.yaml"));
  // When the recorded calibration and frames are played into it
  json actual = json::array();
  ASSERT_NO_FATAL_FAILURE(
      replay.collect({"stereo/calibration", "stereo/frame"}, detection_row, 1500ms, actual));
  ASSERT_FALSE(actual.empty()) << replay.node_output();
  if (sb::replay::regenerate_references()) {
    ASSERT_EQ(actual.size(), static_cast<std::size_t>(sb::replay::kReplayFrames))
        << "regeneration needs every frame answered; run again";
  }
  // Then every answered frame matches the reference: same status, centres and radii within
  // 0.5 px, position within 1 cm; and most frames were answered
  const json reference = sb::replay::reference("ball_detector.json", actual);
  ASSERT_TRUE(reference.is_array())
      << "missing or unreadable " << sb::replay::reference_path("ball_detector.json");
  std::size_t common = 0;
  const auto diffs = sb::replay::compare(
      actual, reference, {"status"},
      {{"left", kCentreTolPx}, {"right", kCentreTolPx}, {"position_m", kPositionTolM}}, common);
  EXPECT_TRUE(diffs.empty()) << diffs.size() << " differences, first:\n"
                             << sb::replay::first_diffs(diffs);
  std::printf("ball_detector answered %zu of %zu frames\n", common, reference.size());
  EXPECT_GE(static_cast<double>(common), kMinFrameCoverage * reference.size())
      << common << " of " << reference.size() << " frames answered";
}

TEST_F(ReplayTest, TrackerDetectionsToTracksMatchTheReference) {
  // Given the tracker node and a reader of its tracks
  NodeReplay<stereoball_msg_BallTrack> replay(*recording_, sb::topics::kBallTrack);
  ASSERT_NO_FATAL_FAILURE(replay.start_node("tracker", "tracker.yaml"));
  // When the recorded calibration and detections are played into it
  json actual = json::array();
  ASSERT_NO_FATAL_FAILURE(
      replay.collect({"stereo/calibration", "ball/detection"}, track_row, 1000ms, actual));
  // Then every detection got a track (reliable topic) equal to the reference: same state,
  // verdict, validity and last-seen side, position within 1 cm
  const json reference = sb::replay::reference("tracker.json", actual);
  ASSERT_TRUE(reference.is_array())
      << "missing or unreadable " << sb::replay::reference_path("tracker.json");
  EXPECT_EQ(actual.size(), reference.size()) << replay.node_output();
  std::size_t common = 0;
  const auto diffs = sb::replay::compare(actual, reference,
                                         {"state", "verdict", "position_valid", "last_seen_side"},
                                         {{"position_m", kPositionTolM}, {"ssd", kSsdTol}}, common);
  EXPECT_TRUE(diffs.empty()) << diffs.size() << " differences, first:\n"
                             << sb::replay::first_diffs(diffs);
  EXPECT_EQ(common, reference.size());
}

TEST_F(ReplayTest, MotionControllerTracksToSettledCommandMatchesTheReference) {
  // Given the motion_controller node and a reader of its commands (receive times kept)
  NodeReplay<stereoball_msg_VelocityCommand> replay(*recording_, sb::topics::kVelocityCommand);
  ASSERT_NO_FATAL_FAILURE(replay.start_node("motion_controller", "motion_controller.yaml"));
  // When the recorded tracks are played into it
  struct Received {
    std::chrono::steady_clock::time_point at;
    double linear, angular;
  };
  std::vector<Received> commands;
  std::chrono::steady_clock::time_point play_end{};
  const auto poll = [&] {
    for (auto& s : replay.take())
      commands.push_back(
          {std::chrono::steady_clock::now(), s.get()->linear_mps, s.get()->angular_radps});
  };
  ASSERT_NO_FATAL_FAILURE(replay.play(
      {"ball/track"},
      [&] {
        poll();
        play_end = std::chrono::steady_clock::now();
      },
      0ms));
  // Commands of the last second of playback: the tracks end with the ball held still for
  // 0.5 s (2 s at rate 0.25), so the controller has settled on a constant target
  std::vector<double> lin, ang;
  for (const auto& c : commands)
    if (c.at > play_end - 1000ms && c.at < play_end - 50ms)
      lin.push_back(c.linear), ang.push_back(c.angular);
  ASSERT_GE(lin.size(), 5u) << commands.size() << " commands\n" << replay.node_output();
  std::sort(lin.begin(), lin.end());
  std::sort(ang.begin(), ang.end());
  const json actual = {{"linear_mps", lin[lin.size() / 2]}, {"angular_radps", ang[ang.size() / 2]}};
  std::printf("settled command %s from %zu commands\n", actual.dump().c_str(), lin.size());
  // Then the settled command (median of that second) matches the reference within
  // 0.01 m/s and 0.01 rad/s
  const json reference = sb::replay::reference("motion_controller.json", actual);
  ASSERT_TRUE(reference.is_object())
      << "missing " << sb::replay::reference_path("motion_controller.json");
  EXPECT_NEAR(actual["linear_mps"].get<double>(), reference["linear_mps"].get<double>(),
              kLinearTolMps)
      << actual.dump();
  EXPECT_NEAR(actual["angular_radps"].get<double>(), reference["angular_radps"].get<double>(),
              kAngularTolRadps)
      << actual.dump();
  // And once the tracks stop, the controller stops the base (stale input)
  EXPECT_TRUE(st::eventually(
      [&] {
        poll();
        return !commands.empty() && commands.back().linear == 0.0 && commands.back().angular == 0.0;
      },
      5s))
      << commands.size() << " commands, the last one not zero";
}

}  // namespace
