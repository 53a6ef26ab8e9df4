#pragma once
// One outgoing stereo frame as views of both eyes (pointers, sizes, encoding), the form every
// frame publisher (camera_server, simulator) builds before filling a stereo/frame message
// (frame_msg.hpp) or compressing the eyes (frame_compressor.hpp). No copies, no IDL types.

#include <opencv2/core.hpp>

#include <cstddef>
#include <cstdint>
#include <string>

#include "common/util/result.hpp"

namespace stereoball::stereo {

/// One eye of an outgoing frame; data stays valid as long as what it points into.
struct EyeView {
  int64_t capture_stamp_ns = 0;
  uint32_t width_px = 0;
  uint32_t height_px = 0;
  uint32_t step_bytes = 0;  ///< 0 for compressed encodings
  const uint8_t* data = nullptr;
  size_t bytes = 0;
};

/// Both eyes plus the pair metadata of stereo/frame.
struct FrameView {
  uint64_t seq = 0;
  int64_t stamp_ns = 0;
  std::string encoding;  ///< "bgr8", "mono8", "yuyv", "jpeg", "png"
  bool rectified = false;
  EyeView left;
  EyeView right;
};

/// The view of an image's pixels (step and byte count of its rows) with a capture stamp.
EyeView eye_view(const cv::Mat& image, int64_t capture_stamp_ns);

/// The pixels of a decoded eye ("bgr8" -> CV_8UC3, "mono8" -> CV_8UC1) without a copy; empty
/// for other encodings.
cv::Mat image_of(const EyeView& eye, const std::string& encoding);

/// View of two decoded images (CV_8UC1 -> "mono8", CV_8UC3 -> "bgr8"); both share one stamp.
Result<FrameView> view_of_images(const cv::Mat& left, const cv::Mat& right, uint64_t seq,
                                 int64_t stamp_ns);

}  // namespace stereoball::stereo
