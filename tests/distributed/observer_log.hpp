#pragma once
// The text lines printed by sb_netns_observer (one sample per line, receive time first) and
// their parser, shared by the two-host test and the distributed benchmark.
//   F rx_ns stamp_ns seq bytes encoding                     stereo/frame
//   G rx_ns stamp_ns frame_seq robot_x robot_y robot_yaw linear angular ball_x ball_y
//   D rx_ns capture_ns publish_ns frame_seq status processing_ms   ball/detection
//   T rx_ns capture_ns publish_ns frame_seq state distance_m bearing_rad    ball/track
//   C rx_ns stamp_ns seq linear_mps angular_radps capture_ns   cmd/velocity
// Times are CLOCK_REALTIME ns since epoch; the namespaces share the clock.

#include <cstdint>
#include <string>
#include <vector>

namespace stereoball::distributed {

/// One received stereo/frame.
struct FrameRx {
  int64_t rx_ns, stamp_ns;
  uint64_t seq, bytes;
  std::string encoding;
};
/// One received sim/ground_truth (robot pose and actual velocity).
struct TruthRx {
  int64_t rx_ns, stamp_ns;
  uint64_t frame_seq;
  double robot_x_m, robot_y_m, robot_yaw_rad, linear_mps, angular_radps, ball_x_m, ball_y_m;
};
/// One received ball/detection.
struct DetectionRx {
  int64_t rx_ns, capture_ns, publish_ns;
  uint64_t frame_seq;
  int status;
  double processing_ms;  ///< detector time from taking the frame to publishing, ms
};
/// One received ball/track (state: 0 idle, 1 following, 2 searching).
struct TrackRx {
  int64_t rx_ns, capture_ns, publish_ns;
  uint64_t frame_seq;
  int state;
  double distance_m, bearing_rad;
};
/// One received cmd/velocity.
struct CommandRx {
  int64_t rx_ns, stamp_ns;
  uint64_t seq;
  double linear_mps, angular_radps;
  int64_t capture_ns;  ///< capture stamp of the track it answers (0: timer or stop command)
};

/// Everything an observer printed so far (malformed or partial lines are skipped).
struct ObserverLog {
  std::vector<FrameRx> frames;
  std::vector<TruthRx> truths;
  std::vector<DetectionRx> detections;
  std::vector<TrackRx> tracks;
  std::vector<CommandRx> commands;
};

/// Parses an observer's output.
ObserverLog parse_observer_log(const std::string& text);

/// Track state value of FOLLOWING in the log (stereoball_msg_TrackState).
constexpr int kTrackFollowing = 1;

}  // namespace stereoball::distributed
