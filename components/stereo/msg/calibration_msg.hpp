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

/// The calibration a message carries, validated (validate_calibration); the error names the
/// bad field. Never trusts the sequence lengths beyond what the message holds.
::stereoball::Result<StereoCalibration> calibration_from_message(
    const stereoball_msg_StereoCalibration& msg);

}  // namespace stereoball::stereo
