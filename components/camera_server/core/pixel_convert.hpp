#pragma once
// Converts captured camera formats to packed BGR (8 bits per channel).

#include <cstdint>
#include <span>

#include <opencv2/core.hpp>

#include "camera_server/core/status.hpp"

namespace stereoball::camera_server {

/// YUYV 4:2:2 (BT.601, limited range) to BGR into `bgr` (reallocated only when the size changes).
/// step_bytes is the source row pitch (>= 2 * width_px). Same result as OpenCV's
/// COLOR_YUV2BGR_YUYV, computed with integer look-up tables in one pass.
Status yuyv_to_bgr(std::span<const uint8_t> yuyv, int width_px, int height_px, int step_bytes,
                   cv::Mat& bgr);

/// Same as yuyv_to_bgr but writes into caller memory (dst_step_bytes >= 3 * width_px), so a
/// converted frame can land directly in an outgoing message buffer.
Status yuyv_to_bgr_into(std::span<const uint8_t> yuyv, int width_px, int height_px, int step_bytes,
                        uint8_t* dst, int dst_step_bytes);

/// Decodes one MJPEG (JPEG) frame to BGR; fails when the data is not a JPEG or when its size
/// differs from width_px x height_px (0 x 0 accepts any size).
Status mjpeg_to_bgr(std::span<const uint8_t> jpeg, int width_px, int height_px, cv::Mat& bgr);

}  // namespace stereoball::camera_server
