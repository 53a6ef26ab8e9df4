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

}  // namespace stereoball::camera_server
