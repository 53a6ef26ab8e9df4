#pragma once
// Turns a raw camera pair or a decoded file pair into the outgoing stereo frame: a view of
// both eyes (pointers, sizes, encoding) ready to be copied into a message.

#include <cstdint>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

#include "camera_server/core/raw_image.hpp"
#include "camera_server/core/status.hpp"
#include "stereo/frame/frame_view.hpp"

namespace stereoball::camera_server {

/// How raw camera frames are published.
struct FrameBuilderParams {
  std::string publish_encoding = "bgr8";  ///< "bgr8" (converted) or "native" (as captured)

  /// Success, or an error naming the bad field and its allowed values.
  Status validate() const;
};

/// Converts raw pairs (YUYV/MJPEG) per the publish encoding, reusing its buffers.
class FrameBuilder {
 public:
  explicit FrameBuilder(const FrameBuilderParams& params);

  /// The outgoing view of a raw pair; points into `pair` (native) or into this builder (bgr8).
  Result<stereo::FrameView> step(const RawStereoPair& pair);

  /// The converted images of the last bgr8 step (empty before).
  const cv::Mat& left_bgr() const { return bgr_[0]; }
  const cv::Mat& right_bgr() const { return bgr_[1]; }

 private:
  Status convert(const RawImage& raw, cv::Mat& out) const;

  FrameBuilderParams params_;
  cv::Mat bgr_[2];
};

}  // namespace stereoball::camera_server
