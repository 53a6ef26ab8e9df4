// The compressed stereo stream end to end: the real simulator process publishing JPEG eyes
// (started as deploy/robot-jpeg.yaml starts it) and the real ball_detector process on a private
// domain; the detector accepts the stream transparently (no BAD_FRAME) and finds the ball where
// the raw stream (deploy/robot.yaml) lets it.

#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/dds/participant.hpp"
#include "common/dds/reader.hpp"
#include "process.hpp"
#include "profile.hpp"
#include "stereoball/topics.hpp"

namespace sb = stereoball;
using namespace std::chrono_literals;
using sb::testing::Process;

namespace {

// What the detector said about the simulator's frames, with the ground truth of each frame.
struct DetectorRun {
  int detections = 0, bad_frames = 0, found = 0, found_with_truth = 0;
  std::vector<double> error_m;  // |detected - true| ball centre, left camera frame, metres
  std::string first_bad_reason;
  std::string log;
};

// The simulator's program and arguments in a deploy/ profile, plus the test scenario.
std::vector<std::string> simulator_of(const std::string& profile_name) {
  auto profile = sb::launch::load_profile(profile_name, SB_SOURCE_DIR);
  EXPECT_TRUE(profile) << profile.error();
  if (!profile) return {};
  for (const auto& node : profile->nodes) {
    if (node.name != "simulator") continue;
    std::vector<std::string> argv{sb::testing::bin(node.program)};
    argv.insert(argv.end(), node.args.begin(), node.args.end());
    argv.insert(argv.end(), {"--scenario", "ball_still_plain"});
    return argv;
  }
  ADD_FAILURE() << profile_name << " has no simulator";
  return {};
}

// Runs the simulator as in deploy/<profile>.yaml + ball_detector until n detections arrived.
DetectorRun run_pipeline(const std::string& profile, int n) {
  const std::string partition = sb::testing::unique_partition() + "." + profile;
  const std::vector<std::string> bus{"--domain", std::to_string(sb::testing::test_domain()),
                                     "--partition", partition};
  auto args = [&](std::vector<std::string> a) {
    a.insert(a.end(), bus.begin(), bus.end());
    return a;
  };
  sb::dds::DomainParticipant participant({sb::testing::test_domain(), partition});
  sb::dds::DataReader<stereoball_msg_BallDetection> detections(participant,
                                                               sb::topics::kBallDetection);
  sb::dds::DataReader<stereoball_msg_GroundTruth> truth(participant, sb::topics::kGroundTruth);
  Process detector = Process::start(args({sb::testing::bin("ball_detector"), "--config",
                                          sb::testing::source_path("config/ball_detector.yaml")}));
  Process simulator = Process::start(args(simulator_of(profile)));
  DetectorRun r;
  std::map<uint64_t, std::array<double, 3>> truth_m;  // frame seq -> ball, left camera frame
  std::vector<sb::dds::Owned<stereoball_msg_BallDetection>> got;
  sb::testing::eventually(
      [&] {
        for (auto& g : truth.take()) {
          truth_m[g->frame_seq] = {g->ball_camera_m[0], g->ball_camera_m[1], g->ball_camera_m[2]};
        }
        for (auto& d : detections.take()) {
          // Frames before the calibration reached the detector say so; they are not counted.
          if (d->status != stereoball_msg_DETECTION_NO_CALIBRATION) got.push_back(std::move(d));
        }
        return static_cast<int>(got.size()) >= n;
      },
      40s);
  for (auto& g : truth.take()) {
    truth_m[g->frame_seq] = {g->ball_camera_m[0], g->ball_camera_m[1], g->ball_camera_m[2]};
  }
  for (const auto& d : got) {
    ++r.detections;
    if (d->status == stereoball_msg_DETECTION_BAD_FRAME) {
      if (r.bad_frames++ == 0) r.first_bad_reason = d->reason;
    }
    if (d->status != stereoball_msg_DETECTION_FOUND) continue;
    ++r.found;
    const auto t = truth_m.find(d->frame_seq);
    if (t == truth_m.end()) continue;
    ++r.found_with_truth;
    r.error_m.push_back(std::sqrt(std::pow(d->position_m[0] - t->second[0], 2) +
                                  std::pow(d->position_m[1] - t->second[1], 2) +
                                  std::pow(d->position_m[2] - t->second[2], 2)));
  }
  simulator.signal(SIGTERM);
  detector.signal(SIGTERM);
  simulator.wait_for_exit(5s);
  detector.wait_for_exit(5s);
  r.log = "--- simulator\n" + simulator.output() + "--- ball_detector\n" + detector.output();
  return r;
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

TEST(CompressedStream, GivenSimulatorJpegFrames_ThenBallDetectorAcceptsThemAndFindsTheBall) {
  // Given the simulator as the robot profile runs it (raw frames), then as the robot-jpeg
  // profile runs it (JPEG q90 frames), of a still one-colour ball
  // When ball_detector runs on each stream for 60 calibrated frames
  const DetectorRun raw = run_pipeline("robot", 60);
  const DetectorRun jpeg = run_pipeline("robot-jpeg", 60);
  std::printf("raw:  %d detections, %d found, median 3D error %.1f mm\n", raw.detections, raw.found,
              1e3 * median(raw.error_m));
  std::printf("jpeg: %d detections, %d found, median 3D error %.1f mm\n", jpeg.detections,
              jpeg.found, 1e3 * median(jpeg.error_m));
  // Then every JPEG frame is decoded and processed: no frame is rejected as bad
  ASSERT_GE(jpeg.detections, 60) << jpeg.log;
  EXPECT_EQ(jpeg.bad_frames, 0) << "first reason: " << jpeg.first_bad_reason;
  EXPECT_EQ(raw.bad_frames, 0) << "first reason: " << raw.first_bad_reason;
  // And JPEG costs at most a few detections and no accuracy worth the name compared with raw
  // (the detector's own quality is judged elsewhere; this compares the two streams)
  EXPECT_GE(jpeg.found, 0.8 * raw.found - 2) << jpeg.log;
  if (!raw.error_m.empty() && !jpeg.error_m.empty()) {
    EXPECT_LT(median(jpeg.error_m), median(raw.error_m) + 0.01);
  }
}

}  // namespace
