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
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "common/dds/participant.hpp"
#include "common/dds/reader.hpp"
#include "process.hpp"
#include "replay_recording.hpp"
#include "stereoball/topics.hpp"

namespace sb = stereoball;
namespace st = stereoball::testing;
using json = nlohmann::json;
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
// Playback slower than recorded so the nodes are never overrun.
constexpr const char* kPlayRate = "0.25";

bool regenerate() {
  const char* v = std::getenv("SB_REGENERATE_REFERENCES");
  return v != nullptr && std::string(v) == "1";
}

std::string config(const std::string& file) {
  const char* dir = std::getenv("SB_REPLAY_CONFIG_DIR");
  return (dir ? std::string(dir) : st::source_path("config")) + "/" + file;
}

std::string reference_path(const std::string& name) {
  return st::source_path("tests/replay/reference/" + name);
}

json load_reference(const std::string& name) {
  std::ifstream in(reference_path(name));
  if (!in) return json();
  return json::parse(in, nullptr, false);
}

void save_reference(const std::string& name, const json& j) {
  std::ofstream out(reference_path(name));
  out << j.dump(1) << "\n";
  std::printf("regenerated %s\n", reference_path(name).c_str());
}

std::vector<std::string> dds_flags(const std::string& partition) {
  return {"--domain", std::to_string(st::test_domain()), "--partition", partition};
}

template <typename T>
sb::topics::QosSpec deep(const sb::topics::Topic<T>& t) {
  sb::topics::QosSpec q = t.spec.qos;
  q.history_depth = 1000;
  q.deadline_ns = 0;
  return q;
}

class ReplayTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::string(st::temp_dir());
    const std::string path = *dir_ + "/replay.mcap";
    const auto error =
        sb::replay::make_replay_recording(path, st::test_domain(), st::unique_partition() + "_gen");
    ASSERT_FALSE(error) << *error;
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

  // Starts a node on partition_ with its config file.
  st::Process start_node(const std::string& name, const std::string& config_file) {
    std::vector<std::string> argv = {st::bin(name), "--config", config(config_file)};
    for (auto& f : dds_flags(partition_)) argv.push_back(f);
    return st::Process::start(argv);
  }

  // Starts stereoball-play of the recording's topics into partition_.
  st::Process start_play(const std::vector<std::string>& topics) {
    std::vector<std::string> argv = {
        st::bin("stereoball-play"), *recording_, "--rate", kPlayRate, "--wait", "2", "--topics"};
    argv.insert(argv.end(), topics.begin(), topics.end());
    for (auto& f : dds_flags(partition_)) argv.push_back(f);
    return st::Process::start(argv);
  }

  // Calls poll every 5 ms while play runs, then for linger after it exits.
  static void pump(st::Process& play, const std::function<void()>& poll,
                   std::chrono::milliseconds linger) {
    const auto deadline = std::chrono::steady_clock::now() + 60s;
    while (play.running() && std::chrono::steady_clock::now() < deadline) {
      poll();
      std::this_thread::sleep_for(5ms);
    }
    const auto end = std::chrono::steady_clock::now() + linger;
    while (std::chrono::steady_clock::now() < end) {
      poll();
      std::this_thread::sleep_for(5ms);
    }
  }

  static std::string* recording_;
  static std::string* dir_;
  std::string partition_ = st::unique_partition();
  sb::dds::DomainParticipant participant_{{st::test_domain(), partition_}};
};

std::string* ReplayTest::recording_ = nullptr;
std::string* ReplayTest::dir_ = nullptr;

json circle(const stereoball_msg_EyeCircle& c) {
  return {c.x_px, c.y_px, c.radius_px};
}

json vec3(const double* v) {
  return {v[0], v[1], v[2]};
}

// Numbers, or arrays of numbers of the same length, equal within tol.
bool near(const json& a, const json& b, double tol) {
  if (a.is_number() && b.is_number()) return std::abs(a.get<double>() - b.get<double>()) <= tol;
  if (!a.is_array() || !b.is_array() || a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::abs(a[i].get<double>() - b[i].get<double>()) > tol) return false;
  return true;
}

// Differences between actual and reference frames keyed by "seq"; only frames in both are
// compared. fields: exact ones; toleranced: {field, tolerance}.
std::vector<std::string> compare(const json& actual, const json& reference,
                                 const std::vector<std::string>& exact,
                                 const std::vector<std::pair<std::string, double>>& toleranced,
                                 std::size_t& common) {
  std::map<std::uint64_t, json> ref;
  for (const auto& f : reference) ref[f["seq"].get<std::uint64_t>()] = f;
  std::vector<std::string> diffs;
  common = 0;
  for (const auto& f : actual) {
    const auto seq = f["seq"].get<std::uint64_t>();
    const auto it = ref.find(seq);
    if (it == ref.end()) {
      diffs.push_back("seq " + std::to_string(seq) + " not in the reference");
      continue;
    }
    ++common;
    const json& r = it->second;
    for (const auto& k : exact)
      if (f[k] != r[k])
        diffs.push_back("seq " + std::to_string(seq) + " " + k + ": " + f[k].dump() +
                        " vs reference " + r[k].dump());
    for (const auto& [k, tol] : toleranced)
      if (!near(f[k], r[k], tol))
        diffs.push_back("seq " + std::to_string(seq) + " " + k + ": " + f[k].dump() +
                        " vs reference " + r[k].dump() + " (tolerance " + std::to_string(tol) +
                        ")");
  }
  return diffs;
}

std::string first(const std::vector<std::string>& diffs, std::size_t n = 10) {
  std::string s;
  for (std::size_t i = 0; i < std::min(n, diffs.size()); ++i) s += diffs[i] + "\n";
  return s;
}

TEST_F(ReplayTest, BallDetectorFramesToDetectionsMatchTheReference) {
  // Given the ball_detector node and a reader of its detections
  sb::dds::DataReader<stereoball_msg_BallDetection> reader(participant_, sb::topics::kBallDetection,
                                                           deep(sb::topics::kBallDetection));
  auto node = start_node("ball_detector", "ball_detector.yaml");
  ASSERT_TRUE(reader.wait_for_writers(1, 15'000'000'000)) << node.output();
  // When the recorded calibration and frames are played into it
  auto play = start_play({"stereo/calibration", "stereo/frame"});
  json actual = json::array();
  pump(
      play,
      [&] {
        for (auto& s : reader.take(64)) {
          const auto& d = *s.get();
          actual.push_back({{"seq", d.frame_seq},
                            {"status", static_cast<int>(d.status)},
                            {"left", circle(d.left)},
                            {"right", circle(d.right)},
                            {"position_m", vec3(d.position_m)}});
        }
      },
      1500ms);
  ASSERT_EQ(play.wait_for_exit(5s), 0) << play.output();
  ASSERT_FALSE(actual.empty()) << node.output();
  if (regenerate()) {
    ASSERT_EQ(actual.size(), static_cast<std::size_t>(sb::replay::kReplayFrames))
        << "regeneration needs every frame answered; run again";
    save_reference("ball_detector.json", actual);
  }
  // Then every answered frame matches the reference: same status, centres and radii within
  // 0.5 px, position within 1 cm; and most frames were answered
  const json reference = load_reference("ball_detector.json");
  ASSERT_TRUE(reference.is_array())
      << "missing or unreadable " << reference_path("ball_detector.json");
  std::size_t common = 0;
  const auto diffs = compare(
      actual, reference, {"status"},
      {{"left", kCentreTolPx}, {"right", kCentreTolPx}, {"position_m", kPositionTolM}}, common);
  EXPECT_TRUE(diffs.empty()) << diffs.size() << " differences, first:\n" << first(diffs);
  std::printf("ball_detector answered %zu of %zu frames\n", common, reference.size());
  EXPECT_GE(static_cast<double>(common), kMinFrameCoverage * reference.size())
      << common << " of " << reference.size() << " frames answered";
}

TEST_F(ReplayTest, TrackerDetectionsToTracksMatchTheReference) {
  // Given the tracker node and a reader of its tracks
  sb::dds::DataReader<stereoball_msg_BallTrack> reader(participant_, sb::topics::kBallTrack,
                                                       deep(sb::topics::kBallTrack));
  auto node = start_node("tracker", "tracker.yaml");
  ASSERT_TRUE(reader.wait_for_writers(1, 15'000'000'000)) << node.output();
  // When the recorded calibration and detections are played into it
  auto play = start_play({"stereo/calibration", "ball/detection"});
  json actual = json::array();
  pump(
      play,
      [&] {
        for (auto& s : reader.take(64)) {
          const auto& t = *s.get();
          actual.push_back({{"seq", t.frame_seq},
                            {"state", static_cast<int>(t.state)},
                            {"verdict", static_cast<int>(t.verdict)},
                            {"position_valid", t.position_valid},
                            {"position_m", vec3(t.position_m)},
                            {"last_seen_side", static_cast<int>(t.last_seen_side)},
                            {"ssd", t.ssd}});
        }
      },
      1000ms);
  ASSERT_EQ(play.wait_for_exit(5s), 0) << play.output();
  if (regenerate()) save_reference("tracker.json", actual);
  // Then every detection got a track (reliable topic) equal to the reference: same state,
  // verdict, validity and last-seen side, position within 1 cm
  const json reference = load_reference("tracker.json");
  ASSERT_TRUE(reference.is_array()) << "missing or unreadable " << reference_path("tracker.json");
  EXPECT_EQ(actual.size(), reference.size()) << node.output();
  std::size_t common = 0;
  const auto diffs =
      compare(actual, reference, {"state", "verdict", "position_valid", "last_seen_side"},
              {{"position_m", kPositionTolM}, {"ssd", kSsdTol}}, common);
  EXPECT_TRUE(diffs.empty()) << diffs.size() << " differences, first:\n" << first(diffs);
  EXPECT_EQ(common, reference.size());
}

TEST_F(ReplayTest, MotionControllerTracksToSettledCommandMatchesTheReference) {
  // Given the motion_controller node and a reader of its commands (receive times kept)
  sb::dds::DataReader<stereoball_msg_VelocityCommand> reader(
      participant_, sb::topics::kVelocityCommand, deep(sb::topics::kVelocityCommand));
  auto node = start_node("motion_controller", "motion_controller.yaml");
  ASSERT_TRUE(reader.wait_for_writers(1, 15'000'000'000)) << node.output();
  // When the recorded tracks are played into it
  auto play = start_play({"ball/track"});
  struct Received {
    std::chrono::steady_clock::time_point at;
    double linear, angular;
  };
  std::vector<Received> commands;
  std::chrono::steady_clock::time_point play_end{};
  const auto poll = [&] {
    for (auto& s : reader.take(64))
      commands.push_back(
          {std::chrono::steady_clock::now(), s.get()->linear_mps, s.get()->angular_radps});
  };
  pump(
      play,
      [&] {
        poll();
        play_end = std::chrono::steady_clock::now();
      },
      0ms);
  ASSERT_EQ(play.wait_for_exit(5s), 0) << play.output();
  // Commands of the last second of playback: the tracks end with the ball held still for
  // 0.5 s (2 s at rate 0.25), so the controller has settled on a constant target
  std::vector<double> lin, ang;
  for (const auto& c : commands)
    if (c.at > play_end - 1000ms && c.at < play_end - 50ms)
      lin.push_back(c.linear), ang.push_back(c.angular);
  ASSERT_GE(lin.size(), 5u) << commands.size() << " commands\n" << node.output();
  std::sort(lin.begin(), lin.end());
  std::sort(ang.begin(), ang.end());
  const json actual = {{"linear_mps", lin[lin.size() / 2]}, {"angular_radps", ang[ang.size() / 2]}};
  std::printf("settled command %s from %zu commands\n", actual.dump().c_str(), lin.size());
  if (regenerate()) save_reference("motion_controller.json", actual);
  // Then the settled command (median of that second) matches the reference within
  // 0.01 m/s and 0.01 rad/s
  const json reference = load_reference("motion_controller.json");
  ASSERT_TRUE(reference.is_object()) << "missing " << reference_path("motion_controller.json");
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
