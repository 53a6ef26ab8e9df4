#include "stereo/frame/eye_pixels.hpp"

#include <cstdint>
#include <span>

#include "stereo/image/yuyv_convert.hpp"

namespace stereoball::stereo {

Result<cv::Mat> eye_pixels(const EyeView& eye, const std::string& encoding, cv::Mat& converted) {
  if (eye.data == nullptr || eye.width_px == 0 || eye.height_px == 0) return Error{"empty image"};
  const int channels = encoding == "bgr8"    ? 3
                       : encoding == "mono8" ? 1
                       : encoding == "yuyv"  ? 2
                                             : 0;
  if (channels == 0)
    return Error{"\"" + encoding + "\" eyes are not raw pixels (bgr8, mono8, yuyv)"};
  if (eye.step_bytes < uint64_t{eye.width_px} * static_cast<uint32_t>(channels) ||
      eye.bytes < uint64_t{eye.step_bytes} * eye.height_px)
    return Error{"image data has " + std::to_string(eye.bytes) + " bytes for " +
                 std::to_string(eye.width_px) + "x" + std::to_string(eye.height_px) +
                 " with step " + std::to_string(eye.step_bytes)};
  const cv::Mat view(static_cast<int>(eye.height_px), static_cast<int>(eye.width_px),
                     CV_8UC(channels), const_cast<uint8_t*>(eye.data), eye.step_bytes);
  if (channels != 2) return view;
  if (eye.width_px % 2 != 0) return Error{"yuyv width " + std::to_string(eye.width_px) + " is odd"};
  // The conversion camera_server's bgr8 and the frame decoder use: every part sees the same bits.
  const Status st = yuyv_to_bgr(std::span<const uint8_t>(eye.data, eye.bytes), view.cols, view.rows,
                                static_cast<int>(eye.step_bytes), converted);
  if (!st) return Error{st.error()};
  return converted;
}

}  // namespace stereoball::stereo
