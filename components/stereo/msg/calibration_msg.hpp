#pragma once
// Conversion between the stereo/calibration message (idl/stereoball.idl) and
// StereoCalibration, in one place for every publisher and reader of the topic.

#include <cstdint>
#include <string>

#include "common/util/result.hpp"
#include "stereo/core/calibration.hpp"
#include "stereoball.h"

namespace stereoball::stereo {

/// The stereo/calibration message of calib, stamped stamp_ns (ns since epoch). The message
/// borrows calib.d1, calib.d2 and source: they must outlive it.
stereoball_msg_StereoCalibration calibration_to_message(const StereoCalibration& calib,
                                                        std::int64_t stamp_ns,
                                                        const std::string& source);

/// Largest image size a calibration message may describe unless the reader sets its own limit.
inline constexpr int kMaxCalibrationSidePx = 16384;

/// The calibration a message carries, validated (validate_calibration); the error names the
/// bad field. Its image size is checked against max_size before anything is allocated (a
/// reader's rectification tables grow with it). Never trusts the sequence lengths beyond what
/// the message holds.
::stereoball::Result<StereoCalibration> calibration_from_message(
    const stereoball_msg_StereoCalibration& msg,
    cv::Size max_size = {kMaxCalibrationSidePx, kMaxCalibrationSidePx});

}  // namespace stereoball::stereo
