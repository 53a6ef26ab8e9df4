#include "camera_server/core/frame_scaler.hpp"

#include <opencv2/imgproc.hpp>

#include "stereo/core/calibration_scaling.hpp"

namespace stereoball::camera_server {

cv::Size FrameScaler::output_size(cv::Size capture) const {
  return stereo::scaled_size(capture, width_px_);
}

Result<stereo::FrameView> FrameScaler::step(const stereo::FrameView& view) {
  const cv::Mat l = stereo::image_of(view.left, view.encoding);
  const cv::Mat r = stereo::image_of(view.right, view.encoding);
  if (l.empty() || r.empty()) {
    return Error{"publish_width_px: " + view.encoding +
                 " frames cannot be scaled (decoded bgr8/mono8 only)"};
  }
  if (l.cols <= width_px_ || r.cols <= width_px_) {
    return Error{"publish_width_px " + std::to_string(width_px_) + " is not smaller than the " +
                 std::to_string(l.cols) + " px wide frames"};
  }
  cv::resize(l, eyes_[0], output_size(l.size()), 0, 0, cv::INTER_AREA);
  cv::resize(r, eyes_[1], output_size(r.size()), 0, 0, cv::INTER_AREA);
  stereo::FrameView out = view;
  out.left = stereo::eye_view(eyes_[0], view.left.capture_stamp_ns);
  out.right = stereo::eye_view(eyes_[1], view.right.capture_stamp_ns);
  return out;
}

}  // namespace stereoball::camera_server
