// sb_truth_tracker: a test stand-in for the workstation's vision (ball_detector + tracker).
// Turns sim/ground_truth into ball/track (FOLLOWING at the true ball position while the ball
// is visible, SEARCHING otherwise), so the link tests exercise the robot side and DDS across
// the link independently of detection quality. Runs in a launch profile like any node.

#include "common/util/cli11.hpp"

#include <cmath>
#include <cstdio>
#include <exception>
#include <string>

#include "common/dds/reader.hpp"
#include "common/dds/writer.hpp"
#include "common/node/common_flags.hpp"
#include "common/node/node_runner.hpp"
#include "stereoball/topics.hpp"

namespace sb = stereoball;

namespace {

// The track a perfect tracker would publish for this ground truth.
stereoball_msg_BallTrack track_from_truth(const stereoball_msg_GroundTruth& g, int64_t now_ns,
                                          int64_t& last_accepted_ns) {
  stereoball_msg_BallTrack t{};
  t.frame_seq = g.frame_seq;
  t.capture_stamp_ns = g.stamp_ns;
  t.publish_stamp_ns = now_ns;
  t.reason = const_cast<char*>("ground truth");
  t.ssd = -1;
  const bool visible = g.ball_present && g.ball_visible_left && g.ball_visible_right;
  if (visible) {
    last_accepted_ns = g.stamp_ns;
    t.state = stereoball_msg_TRACK_FOLLOWING;
    t.verdict = stereoball_msg_VERDICT_BLOCK_MATCH_ACCEPTED;
    t.position_valid = true;
    for (int i = 0; i < 3; ++i) t.position_m[i] = g.ball_camera_m[i];
    t.bearing_rad = std::atan2(g.ball_camera_m[0], g.ball_camera_m[2]);
    t.distance_m = std::hypot(g.ball_camera_m[0], g.ball_camera_m[2]);
    t.last_seen_side = t.bearing_rad >= 0 ? stereoball_msg_SIDE_RIGHT : stereoball_msg_SIDE_LEFT;
  } else {
    t.state = stereoball_msg_TRACK_SEARCHING;
    t.verdict = stereoball_msg_VERDICT_NO_DETECTION;
  }
  t.last_accepted_stamp_ns = last_accepted_ns;
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  sb::node::block_termination_signals();
  CLI::App app{"sb_truth_tracker: ball/track from sim/ground_truth (test stand-in for vision)"};
  sb::node::CommonOptions common;
  sb::node::add_common_flags(app, common, "", false);
  CLI11_PARSE(app, argc, argv);
  try {
    sb::node::Runner runner("truth_tracker", common);
    sb::dds::DataReader<stereoball_msg_GroundTruth> truths(runner.participant(),
                                                           sb::topics::kGroundTruth);
    sb::dds::DataWriter<stereoball_msg_BallTrack> tracks(runner.participant(),
                                                         sb::topics::kBallTrack);
    int64_t last_accepted_ns = 0;
    runner.on_data(truths.handle(), [&] {
      for (auto& g : truths.take()) {
        tracks.write(track_from_truth(*g, sb::node::now_ns(), last_accepted_ns));
      }
    });
    return runner.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sb_truth_tracker: %s\n", e.what());
    return 1;
  }
}
