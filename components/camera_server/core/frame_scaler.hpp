#pragma once
// Scales both decoded eyes of an outgoing frame to the configured publish width (camera_server
// `publish_width_px`), area interpolation, height in proportion. Pure (image arithmetic only).

#include <opencv2/core.hpp>

#include "common/util/result.hpp"
#include "stereo/frame/frame_view.hpp"

namespace stereoball::camera_server {

/// Reuses its two eye buffers from frame to frame.
class FrameScaler {
 public:
  /// width_px: the published width, > 0 and even (validated with the parameters).
  explicit FrameScaler(int width_px) : width_px_(width_px) {}

  /// The published size of a frame captured at `capture` (stereo::scaled_size).
  cv::Size output_size(cv::Size capture) const;

  /// The view of both eyes scaled (cv::INTER_AREA) into this scaler's buffers, with the
  /// frame's seq, stamps and flags. An error for an encoding that is not decoded pixels
  /// (bgr8/mono8) or a frame not wider than the publish width.
  Result<stereo::FrameView> step(const stereo::FrameView& view);

 private:
  int width_px_;
  cv::Mat eyes_[2];
};

}  // namespace stereoball::camera_server
