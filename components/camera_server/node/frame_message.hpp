#pragma once
// Core views <-> generated IDL structs for stereo/frame and stereo/calibration.

#include <string>

#include "camera_server/core/frame_builder.hpp"
#include "stereo/core/calibration.hpp"
#include "stereoball.h"

namespace stereoball::camera_server {

/// Fills msg so that it points at the view's pixels and at `source` (no copy; valid while
/// both live). dds write() serializes before returning.
void fill_frame_message(const FrameView& view, const std::string& source,
                        stereoball_msg_StereoFrame& msg);

/// Fills msg from a calibration; d1/d2 and source point into calib/source (keep them alive).
void fill_calibration_message(const stereo::StereoCalibration& calib, const std::string& source,
                              int64_t stamp_ns, stereoball_msg_StereoCalibration& msg);

}  // namespace stereoball::camera_server
