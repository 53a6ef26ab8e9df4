#pragma once
// Turns a raw camera pair or a decoded file pair into the outgoing stereo frame: a view of
// both eyes (pointers, sizes, encoding) ready to be copied into a message.

#include <cstdint>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

#include "camera_server/core/raw_image.hpp"
#include "camera_server/core/status.hpp"

namespace stereoball::camera_server {

/// One eye of an outgoing frame; data stays valid until the next FrameBuilder::step.
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
  std::string encoding;  ///< "bgr8", "mono8", "yuyv", "jpeg"
  bool rectified = false;
  EyeView left;
  EyeView right;
};

/// How raw camera frames are published.
struct FrameBuilderParams {
  std::string publish_encoding = "bgr8";  ///< "bgr8" (converted) or "native" (as captured)

  /// Names the bad field and its allowed values, or nullopt.
  std::optional<std::string> validate() const;
};

/// Converts raw pairs (YUYV/MJPEG) per the publish encoding, reusing its buffers.
class FrameBuilder {
 public:
  explicit FrameBuilder(const FrameBuilderParams& params);

  /// The outgoing view of a raw pair; points into `pair` (native) or into this builder (bgr8).
  Result<FrameView> step(const RawStereoPair& pair);

  /// The converted images of the last bgr8 step (empty before).
  const cv::Mat& left_bgr() const { return bgr_[0]; }
  const cv::Mat& right_bgr() const { return bgr_[1]; }

 private:
  Status convert(const RawImage& raw, cv::Mat& out) const;

  FrameBuilderParams params_;
  cv::Mat bgr_[2];
};

/// The pixels of a decoded eye ("bgr8" -> CV_8UC3, "mono8" -> CV_8UC1) without a copy; empty
/// for other encodings.
cv::Mat image_of(const EyeView& eye, const std::string& encoding);

/// View of two decoded images (CV_8UC1 -> "mono8", CV_8UC3 -> "bgr8"); both share one stamp.
Result<FrameView> view_of_images(const cv::Mat& left, const cv::Mat& right, uint64_t seq,
                                 int64_t stamp_ns);

}  // namespace stereoball::camera_server
