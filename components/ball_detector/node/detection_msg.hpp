#pragma once
// IDL <-> core conversions of the ball detector: pipeline result to ball/detection, ball/track
// to the pairing prior (stereo/calibration: stereo/msg/calibration_msg.hpp).

#include <cstdint>
#include <string>

#include "ball_detector/pipeline/pairing.hpp"
#include "ball_detector/pipeline/stereo_pipeline.hpp"
#include "stereoball.h"

namespace stereoball::ball_detector {

/// The parts of a ball/track sample the detector uses as a prior.
TrackedBall from_message(const stereoball_msg_BallTrack& msg);

/// Frame identity a detection refers to.
struct FrameStamp {
  std::uint64_t seq = 0;      ///< StereoFrame.seq
  std::int64_t stamp_ns = 0;  ///< StereoFrame.stamp_ns, ns since epoch
};

/// Fills msg from a pipeline result; msg.reason points into det.reason (det must outlive msg).
void to_message(const StereoDetection& det, const FrameStamp& frame, float processing_ms,
                std::int64_t publish_stamp_ns, stereoball_msg_BallDetection& msg);

/// The IDL status for a pipeline status.
stereoball_msg_DetectionStatus to_message(DetectionStatus status);

}  // namespace stereoball::ball_detector
