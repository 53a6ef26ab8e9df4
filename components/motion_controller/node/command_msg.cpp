#include "motion_controller/node/command_msg.hpp"

#include <cmath>

namespace stereoball::motion_controller {

TrackState from_msg(stereoball_msg_TrackState s) {
  switch (s) {
    case stereoball_msg_TRACK_FOLLOWING:
      return TrackState::kFollowing;
    case stereoball_msg_TRACK_SEARCHING:
      return TrackState::kSearching;
    default:
      return TrackState::kIdle;  // unknown values stand the robot still
  }
}

Side from_msg(stereoball_msg_Side s) {
  switch (s) {
    case stereoball_msg_SIDE_LEFT:
      return Side::kLeft;
    case stereoball_msg_SIDE_RIGHT:
      return Side::kRight;
    default:
      return Side::kUnknown;
  }
}

TrackSample to_sample(const stereoball_msg_BallTrack& msg) {
  TrackSample t;
  t.state = from_msg(msg.state);
  t.position_valid =
      msg.position_valid && std::isfinite(msg.bearing_rad) && std::isfinite(msg.distance_m);
  t.bearing_rad = t.position_valid ? msg.bearing_rad : 0.0;
  t.distance_m = t.position_valid ? msg.distance_m : 0.0;
  if (t.position_valid) {
    const PolarRates rates =
        polar_rates(msg.position_m[0], msg.position_m[2], msg.velocity_mps[0], msg.velocity_mps[2]);
    t.bearing_rate_radps = rates.bearing_radps;
    t.distance_rate_mps = rates.range_mps;
  }
  t.last_seen_side = from_msg(msg.last_seen_side);
  t.capture_stamp_ns = msg.capture_stamp_ns;
  t.last_accepted_stamp_ns = msg.last_accepted_stamp_ns;
  return t;
}

void to_message(const Command& command, std::uint64_t seq, std::int64_t stamp_ns,
                stereoball_msg_VelocityCommand& out) {
  static char kSource[] = "motion_controller";
  out.seq = seq;
  out.stamp_ns = stamp_ns;
  out.capture_stamp_ns = command.capture_stamp_ns;
  out.linear_mps = command.linear_mps;
  out.angular_radps = command.angular_radps;
  out.source = kSource;
}

}  // namespace stereoball::motion_controller
