#include "tracker/node/track_msg.hpp"

#include <algorithm>
#include <cmath>

namespace stereoball::tracker {
namespace {

stereoball_msg_TrackState to_msg(TrackState s) {
  switch (s) {
    case TrackState::kFollowing:
      return stereoball_msg_TRACK_FOLLOWING;
    case TrackState::kSearching:
      return stereoball_msg_TRACK_SEARCHING;
    case TrackState::kIdle:
      break;
  }
  return stereoball_msg_TRACK_IDLE;
}

stereoball_msg_Side to_msg(Side s) {
  switch (s) {
    case Side::kLeft:
      return stereoball_msg_SIDE_LEFT;
    case Side::kRight:
      return stereoball_msg_SIDE_RIGHT;
    case Side::kUnknown:
      break;
  }
  return stereoball_msg_SIDE_UNKNOWN;
}

stereoball_msg_TrackVerdict to_msg(Verdict v) {
  switch (v) {
    case Verdict::kNoDetection:
      return stereoball_msg_VERDICT_NO_DETECTION;
    case Verdict::kStartupCollecting:
      return stereoball_msg_VERDICT_STARTUP_COLLECTING;
    case Verdict::kStartupInconsistent:
      return stereoball_msg_VERDICT_STARTUP_INCONSISTENT;
    case Verdict::kStartupAccepted:
      return stereoball_msg_VERDICT_STARTUP_ACCEPTED;
    case Verdict::kBlockMatchAccepted:
      return stereoball_msg_VERDICT_BLOCK_MATCH_ACCEPTED;
    case Verdict::kStatisticsAccepted:
      return stereoball_msg_VERDICT_STATISTICS_ACCEPTED;
    case Verdict::kRejected:
      break;
  }
  return stereoball_msg_VERDICT_REJECTED;
}

}  // namespace

ConvertedDetection to_detection(const stereoball_msg_BallDetection& msg,
                                std::uint32_t image_width_px) {
  ConvertedDetection out;
  if (msg.status != stereoball_msg_DETECTION_FOUND) return out;
  const Eigen::Vector3d p(msg.position_m[0], msg.position_m[1], msg.position_m[2]);
  if (!p.allFinite() || !(p.z() > 0.0)) {
    out.problem = "FOUND detection with an invalid position (non-finite or depth <= 0)";
    return out;
  }
  Detection& d = out.detection;
  d.found = true;
  d.position_m = p;
  d.left_x_px = std::isfinite(msg.left.x_px) ? msg.left.x_px : 0.0;
  // Without a width the core takes the last-seen side from the sign of x.
  d.image_width_px = std::isfinite(msg.left.x_px) ? image_width_px : 0;
  d.patch_valid = msg.patch_valid;
  std::copy(std::begin(msg.patch_rgb), std::end(msg.patch_rgb), d.patch_rgb.begin());
  return out;
}

void to_message(const Track& track, std::uint64_t frame_seq, std::int64_t capture_stamp_ns,
                std::int64_t publish_stamp_ns, stereoball_msg_BallTrack& out) {
  out.frame_seq = frame_seq;
  out.capture_stamp_ns = capture_stamp_ns;
  out.publish_stamp_ns = publish_stamp_ns;
  out.state = to_msg(track.state);
  out.verdict = to_msg(track.verdict);
  out.reason = const_cast<char*>(track.reason.c_str());
  out.position_valid = track.position_valid;
  for (int i = 0; i < 3; ++i) {
    out.position_m[i] = track.position_m(i);
    out.velocity_mps[i] = track.velocity_mps(i);
  }
  out.bearing_rad = track.bearing_rad;
  out.distance_m = track.distance_m;
  out.last_seen_side = to_msg(track.last_seen_side);
  out.ssd = track.ssd;
  out.last_accepted_stamp_ns = track.last_accepted_stamp_ns;
}

}  // namespace stereoball::tracker
