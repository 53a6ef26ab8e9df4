#include "ball_detector/node/detection_msg.hpp"

#include <algorithm>
#include <cmath>

namespace stereoball::ball_detector {
namespace {

void fill_circle(const Circle& c, stereoball_msg_EyeCircle& out) {
  out.x_px = static_cast<float>(c.x_px);
  out.y_px = static_cast<float>(c.y_px);
  out.radius_px = static_cast<float>(c.radius_px);
  out.score = static_cast<float>(c.score);
}

}  // namespace

stereoball_msg_DetectionStatus to_message(DetectionStatus status) {
  switch (status) {
    case DetectionStatus::kFound:
      return stereoball_msg_DETECTION_FOUND;
    case DetectionStatus::kNoCandidate:
      return stereoball_msg_DETECTION_NO_CANDIDATE;
    case DetectionStatus::kEpipolarMismatch:
      return stereoball_msg_DETECTION_EPIPOLAR_MISMATCH;
    case DetectionStatus::kSizeInconsistent:
      return stereoball_msg_DETECTION_SIZE_INCONSISTENT;
    case DetectionStatus::kNoCalibration:
      return stereoball_msg_DETECTION_NO_CALIBRATION;
    case DetectionStatus::kBadFrame:
      return stereoball_msg_DETECTION_BAD_FRAME;
    case DetectionStatus::kOffFloor:
      return stereoball_msg_DETECTION_OFF_FLOOR;
    case DetectionStatus::kInteriorMismatch:
      return stereoball_msg_DETECTION_INTERIOR_MISMATCH;
  }
  return stereoball_msg_DETECTION_BAD_FRAME;
}

void to_message(const StereoDetection& det, const FrameStamp& frame, float processing_ms,
                std::int64_t publish_stamp_ns, stereoball_msg_BallDetection& msg) {
  msg.frame_seq = frame.seq;
  msg.capture_stamp_ns = frame.stamp_ns;
  msg.publish_stamp_ns = publish_stamp_ns;
  msg.status = to_message(det.status);
  msg.reason = const_cast<char*>(det.reason.c_str());
  fill_circle(det.left, msg.left);
  fill_circle(det.right, msg.right);
  msg.row_residual_px = static_cast<float>(det.row_residual_px);
  const bool found = det.status == DetectionStatus::kFound;
  for (int i = 0; i < 3; ++i) msg.position_m[i] = found ? det.position_m[i] : 0.0;
  msg.depth_from_size_m = static_cast<float>(det.depth_from_size_m);
  msg.candidates_left = static_cast<std::uint32_t>(std::max(det.candidates_left, 0));
  msg.candidates_right = static_cast<std::uint32_t>(std::max(det.candidates_right, 0));
  msg.processing_ms = processing_ms;
  msg.patch_valid = det.patch_valid;
  std::copy(det.patch_rgb.begin(), det.patch_rgb.end(), msg.patch_rgb);
}

TrackedBall from_message(const stereoball_msg_BallTrack& msg) {
  TrackedBall t;
  t.following = msg.state == stereoball_msg_TRACK_FOLLOWING;
  t.position_valid = msg.position_valid;
  t.position_m = {msg.position_m[0], msg.position_m[1], msg.position_m[2]};
  t.velocity_mps = {msg.velocity_mps[0], msg.velocity_mps[1], msg.velocity_mps[2]};
  t.capture_stamp_ns = msg.capture_stamp_ns;
  // A non-finite field (a corrupt sample) must not steer the pairing.
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(t.position_m[i]) || !std::isfinite(t.velocity_mps[i]))
      t.position_valid = false;
  return t;
}

}  // namespace stereoball::ball_detector
