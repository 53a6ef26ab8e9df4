#pragma once
// Converts MJPEG camera frames to packed BGR (8 bits per channel). YUYV goes through the
// conversion shared with the frame decoder, stereo/image/yuyv_convert.hpp.

#include <cstdint>
#include <span>

#include <opencv2/core.hpp>

#include "camera_server/core/status.hpp"

namespace stereoball::camera_server {

/// Decodes one MJPEG (JPEG) frame to BGR; fails when the data is not a JPEG or when its size
/// differs from width_px x height_px (0 x 0 accepts any size).
Status mjpeg_to_bgr(std::span<const uint8_t> jpeg, int width_px, int height_px, cv::Mat& bgr);

}  // namespace stereoball::camera_server
