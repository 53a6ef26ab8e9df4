#pragma once
// Conversion between the IDL messages (ball/detection, ball/track) and the
// tracker core's value types.

#include <cstdint>
#include <optional>
#include <string>

#include "stereoball.h"
#include "tracker/core/types.hpp"

namespace stereoball::tracker {

/// A detection message as the core sees it, or the reason it is unusable.
struct ConvertedDetection {
  Detection detection;                 ///< found = false when the message is unusable
  std::optional<std::string> problem;  ///< set when a FOUND message carried bad numbers
};

/// Converts ball/detection; image_width_px comes from stereo/calibration (0 = unknown).
/// FOUND with a non-finite or non-positive-depth position is reported as a problem.
ConvertedDetection to_detection(const stereoball_msg_BallDetection& msg,
                                std::uint32_t image_width_px);

/// Fills ball/track from a core track; out.reason points into track.reason (keep it alive).
void to_message(const Track& track, std::uint64_t frame_seq, std::int64_t capture_stamp_ns,
                std::int64_t publish_stamp_ns, stereoball_msg_BallTrack& out);

}  // namespace stereoball::tracker
