#include "tracker/node/tracker_node.hpp"

#include <string>

#include "common/util/log.hpp"
#include "tracker/node/track_msg.hpp"

namespace stereoball::tracker {
namespace {

// A capture stamp this far in the past of the previous one means the source
// restarted (e.g. a replay looped): old positions and blocks are meaningless.
constexpr std::int64_t kTimeJumpBackNs = 1'000'000'000;
// No detection for this long makes the node report itself unhealthy.
constexpr std::int64_t kInputTimeoutNs = 2'000'000'000;

}  // namespace

TrackerNode::TrackerNode(node::Runner& runner, const TrackerParams& params)
    : runner_(runner),
      tracker_(params),
      detections_(runner.participant(), topics::kBallDetection),
      calibration_(runner.participant(), topics::kStereoCalibration),
      tracks_(runner.participant(), topics::kBallTrack) {
  runner_.on_data(detections_.handle(), [this] { on_detections(); });
  runner_.on_data(calibration_.handle(), [this] { on_calibration(); });
  runner_.every(1'000'000'000, [this](std::int64_t now_ns) { check_input(now_ns); });
  runner_.health().set_state(false, "waiting for ball/detection");
}

void TrackerNode::on_calibration() {
  if (auto c = calibration_.take_latest()) {
    if ((*c)->width_px != image_width_px_) {
      image_width_px_ = (*c)->width_px;
      log::info("image width ", image_width_px_, " px from stereo/calibration");
    }
  }
}

void TrackerNode::on_detections() {
  for (auto& sample : detections_.take()) handle(*sample);
}

void TrackerNode::handle(const stereoball_msg_BallDetection& msg) {
  const std::int64_t now_ns = node::now_ns();
  last_received_ns_ = now_ns;
  runner_.health().count(std::string(topics::kBallDetection.spec.name));
  // A frame the detector could not read says nothing about the ball, and its stamp is not to be
  // trusted (a garbage stereo/frame sample carries any stamp): it neither resets the tracker
  // nor advances its time, so a flood of garbage frames cannot make the robot drop the ball.
  if (msg.status == stereoball_msg_DETECTION_BAD_FRAME) {
    runner_.health().set_counter("bad_frames_ignored", ++bad_frames_ignored_);
    return;
  }
  if (last_capture_ns_ && msg.capture_stamp_ns < *last_capture_ns_ - kTimeJumpBackNs) {
    log::warn("capture stamps jumped back ", (*last_capture_ns_ - msg.capture_stamp_ns) / 1'000'000,
              " ms: tracker reset");
    runner_.health().error("time_jump", "capture stamps jumped back; tracker reset");
    tracker_.reset();
  }
  last_capture_ns_ = msg.capture_stamp_ns;

  const ConvertedDetection in = to_detection(msg, image_width_px_);
  if (in.problem) runner_.health().error("bad_detection", *in.problem);
  const Track track = tracker_.step(in.detection, msg.capture_stamp_ns);

  stereoball_msg_BallTrack out{};
  to_message(track, msg.frame_seq, msg.capture_stamp_ns, node::now_ns(), out);
  tracks_.write(out);
  runner_.health().count(std::string(topics::kBallTrack.spec.name));
  const auto v = static_cast<std::size_t>(track.verdict);
  runner_.health().set_counter("verdict_" + std::string(to_string(track.verdict)),
                               ++verdict_counts_[v]);
  runner_.health().set_state(true, std::string(to_string(track.state)));
  if (track.state != last_state_) {
    log::info("state ", to_string(last_state_), " -> ", to_string(track.state), " (",
              to_string(track.verdict), ": ", track.reason, ", last seen ",
              to_string(track.last_seen_side), ")");
    last_state_ = track.state;
  }
}

void TrackerNode::check_input(std::int64_t now_ns) {
  if (now_ns - last_received_ns_ > kInputTimeoutNs) {
    runner_.health().set_state(false, "no ball/detection for 2 s");
  }
}

}  // namespace stereoball::tracker
