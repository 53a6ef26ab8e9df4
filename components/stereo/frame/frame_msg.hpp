#pragma once
// The stereo/frame message of a frame view, as every frame publisher fills it.

#include <string>

#include "stereo/frame/frame_view.hpp"
#include "stereoball.h"

namespace stereoball::stereo {

/// Fills one eye of a message (stereo/frame, stereo/preview) so that it points at the view's
/// bytes (no copy).
void fill_eye_message(const EyeView& view, stereoball_msg_EyeImage& msg);

/// Fills msg so that it points at the view's pixels and at `source` (no copy; valid while
/// both live). dds write() serializes before returning.
void fill_frame_message(const FrameView& view, const std::string& source,
                        stereoball_msg_StereoFrame& msg);

}  // namespace stereoball::stereo
