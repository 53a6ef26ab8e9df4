#include "camera_server/core/pixel_convert.hpp"

#include <string>

#include <opencv2/imgcodecs.hpp>

namespace stereoball::camera_server {
namespace {

std::string size_text(int w, int h) {
  return std::to_string(w) + "x" + std::to_string(h);
}

}  // namespace

Status mjpeg_to_bgr(std::span<const uint8_t> jpeg, int width_px, int height_px, cv::Mat& bgr) {
  // SOI marker: anything else is not a JPEG (imdecode would try other codecs).
  if (jpeg.size() < 4 || jpeg[0] != 0xFF || jpeg[1] != 0xD8) {
    return fail("MJPEG frame is not a JPEG (" + std::to_string(jpeg.size()) +
                " bytes, no start-of-image marker)");
  }
  const cv::Mat raw(1, static_cast<int>(jpeg.size()), CV_8UC1, const_cast<uint8_t*>(jpeg.data()));
  cv::Mat decoded = cv::imdecode(raw, cv::IMREAD_COLOR);
  if (decoded.empty()) {
    return fail("MJPEG frame could not be decoded (" + std::to_string(jpeg.size()) +
                " bytes, corrupt or truncated)");
  }
  if ((width_px != 0 || height_px != 0) &&
      (decoded.cols != width_px || decoded.rows != height_px)) {
    return fail("MJPEG frame is " + size_text(decoded.cols, decoded.rows) + ", expected " +
                size_text(width_px, height_px));
  }
  bgr = std::move(decoded);
  return {};
}

}  // namespace stereoball::camera_server
