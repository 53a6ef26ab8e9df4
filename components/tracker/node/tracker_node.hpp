#pragma once
// The tracker process: takes ball/detection (and the image width from
// stereo/calibration), runs the tracker core, publishes ball/track.

#include <array>
#include <cstdint>
#include <optional>

#include "common/dds/reader.hpp"
#include "common/dds/writer.hpp"
#include "common/node/node_runner.hpp"
#include "tracker/core/tracker.hpp"

namespace stereoball::tracker {

/// Wires the tracker core to its topics on a runner.
class TrackerNode {
 public:
  /// Creates readers/writers on runner's participant and registers callbacks.
  TrackerNode(node::Runner& runner, const TrackerParams& params);

 private:
  void on_detections();
  void on_calibration();
  void handle(const stereoball_msg_BallDetection& msg);
  void check_input(std::int64_t now_ns);

  node::Runner& runner_;
  Tracker tracker_;
  dds::DataReader<stereoball_msg_BallDetection> detections_;
  dds::DataReader<stereoball_msg_StereoCalibration> calibration_;
  dds::DataWriter<stereoball_msg_BallTrack> tracks_;
  std::uint32_t image_width_px_ = 0;
  std::optional<std::int64_t> last_capture_ns_;
  std::uint64_t bad_frames_ignored_ = 0;  // BAD_FRAME detections skipped (health counter)
  std::int64_t last_received_ns_ = 0;
  TrackState last_state_ = TrackState::kIdle;
  std::array<std::uint64_t, 7> verdict_counts_{};  // indexed by Verdict
};

}  // namespace stereoball::tracker
