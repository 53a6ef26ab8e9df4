#pragma once
// The eyes camera_server rectifies: decoded pixels only. The config refuses `rectify` with
// undecoded (native yuyv/jpeg) frames; a frame that gets past it all the same must be an error,
// never published as it came as if it had been rectified.

#include <array>

#include <opencv2/core.hpp>

#include "common/util/result.hpp"
#include "stereo/frame/frame_view.hpp"

namespace stereoball::camera_server {

/// Both eyes of view as images (no copy) for stereo::Rectifier; an error naming the encoding
/// unless it is bgr8 or mono8 with pixels in both eyes.
Result<std::array<cv::Mat, 2>> rectify_input(const stereo::FrameView& view);

}  // namespace stereoball::camera_server
