#pragma once
// IDL <-> core conversions of the ball detector: stereo/calibration to the stereo core's
// calibration (and back, for publishers and tests), pipeline result to ball/detection.

#include <cstdint>
#include <string>

#include "ball_detector/node/pairing.hpp"
#include "ball_detector/node/stereo_pipeline.hpp"
#include "common/util/result.hpp"
#include "stereo/core/calibration.hpp"
#include "stereoball.h"

namespace stereoball::ball_detector {

/// Copies a calibration message into the core struct and validates it; the error names the
/// bad field (e.g. "d1: 3 coefficients, expected 0, 4, 5, 8, 12 or 14").
Result<stereo::StereoCalibration> from_message(const stereoball_msg_StereoCalibration& msg);

/// The parts of a ball/track sample the detector uses as a prior.
TrackedBall from_message(const stereoball_msg_BallTrack& msg);

/// Fills msg from calib; msg's sequences and strings point into calib and source, which must
/// outlive msg (write() serializes them).
void to_message(const stereo::StereoCalibration& calib, const std::string& source,
                std::int64_t stamp_ns, stereoball_msg_StereoCalibration& msg);

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
