#include "stereo/frame/frame_view.hpp"

namespace stereoball::stereo {

EyeView eye_view(const cv::Mat& m, int64_t stamp_ns) {
  return EyeView{stamp_ns,
                 static_cast<uint32_t>(m.cols),
                 static_cast<uint32_t>(m.rows),
                 static_cast<uint32_t>(m.step),
                 m.data,
                 m.step * static_cast<size_t>(m.rows)};
}

cv::Mat image_of(const EyeView& eye, const std::string& encoding) {
  if (encoding != "bgr8" && encoding != "mono8") return {};
  return cv::Mat(static_cast<int>(eye.height_px), static_cast<int>(eye.width_px),
                 encoding == "bgr8" ? CV_8UC3 : CV_8UC1, const_cast<uint8_t*>(eye.data),
                 eye.step_bytes);
}

Result<FrameView> view_of_images(const cv::Mat& left, const cv::Mat& right, uint64_t seq,
                                 int64_t stamp_ns) {
  if (left.empty() || right.empty()) return Error{"empty image in a file pair"};
  if (left.size() != right.size() || left.type() != right.type()) {
    return Error{"left and right images differ in size or type"};
  }
  if (left.type() != CV_8UC1 && left.type() != CV_8UC3) {
    return Error{"images must be 8-bit grey or BGR"};
  }
  FrameView v;
  v.seq = seq;
  v.stamp_ns = stamp_ns;
  v.encoding = left.channels() == 1 ? "mono8" : "bgr8";
  v.left = eye_view(left, stamp_ns);
  v.right = eye_view(right, stamp_ns);
  return v;
}

}  // namespace stereoball::stereo
