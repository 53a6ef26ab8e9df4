#pragma once
// A camera's YUYV 4:2:2 bytes to packed BGR, the one conversion every part uses: camera_server
// (publish_encoding: bgr8) and the frame decoder (yuyv frames) give the same bits.

#include <opencv2/core.hpp>

#include <cstdint>
#include <span>

#include "common/util/result.hpp"

namespace stereoball::stereo {

/// YUYV 4:2:2 (BT.601, limited range) to BGR into `bgr` (reallocated only when the size changes).
/// step_bytes is the source row pitch (>= 2 * width_px). Same result as OpenCV's
/// COLOR_YUV2BGR_YUYV, computed with integer look-up tables in one pass.
Status yuyv_to_bgr(std::span<const std::uint8_t> yuyv, int width_px, int height_px, int step_bytes,
                   cv::Mat& bgr);

/// Same as yuyv_to_bgr but writes into caller memory (dst_step_bytes >= 3 * width_px), so a
/// converted frame can land directly in an outgoing message buffer.
Status yuyv_to_bgr_into(std::span<const std::uint8_t> yuyv, int width_px, int height_px,
                        int step_bytes, std::uint8_t* dst, int dst_step_bytes);

}  // namespace stereoball::stereo
