#include "viewer/bridge/eye_encoder.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstring>

namespace stereoball::viewer {
namespace {

constexpr uint32_t kMaxSidePx = 8192;  // bound every decoded size before touching the bytes

Result<cv::Mat> raw_view(const stereoball_msg_EyeImage& image, int type, uint32_t bytes_per_px) {
  if (image.width_px == 0 || image.height_px == 0 || image.width_px > kMaxSidePx ||
      image.height_px > kMaxSidePx)
    return Error{"image size " + std::to_string(image.width_px) + "x" +
                 std::to_string(image.height_px) + " is outside 1..8192"};
  if (image.step_bytes < image.width_px * bytes_per_px)
    return Error{"step_bytes " + std::to_string(image.step_bytes) + " is smaller than a row"};
  const uint64_t need = uint64_t{image.step_bytes} * image.height_px;
  if (image.data._buffer == nullptr || image.data._length < need)
    return Error{"image data has " + std::to_string(image.data._length) + " bytes, expected " +
                 std::to_string(need) + " (truncated)"};
  return cv::Mat(static_cast<int>(image.height_px), static_cast<int>(image.width_px), type,
                 image.data._buffer, image.step_bytes);
}

Result<cv::Mat> to_bgr(const stereoball_msg_EyeImage& image, const std::string& encoding) {
  if (encoding == "bgr8") return raw_view(image, CV_8UC3, 3);
  if (encoding == "mono8") return raw_view(image, CV_8UC1, 1);
  if (encoding == "yuyv") {
    auto view = raw_view(image, CV_8UC2, 2);
    if (!view) return Error{view.error()};
    cv::Mat bgr;
    cv::cvtColor(*view, bgr, cv::COLOR_YUV2BGR_YUYV);
    return bgr;
  }
  if (encoding == "png") {
    if (image.data._buffer == nullptr || image.data._length == 0) return Error{"png data is empty"};
    cv::Mat decoded;
    try {
      decoded =
          cv::imdecode(cv::Mat(1, static_cast<int>(image.data._length), CV_8U, image.data._buffer),
                       cv::IMREAD_COLOR);
    } catch (const cv::Exception&) {
    }
    if (decoded.empty()) return Error{"png data could not be decoded"};
    return decoded;
  }
  return Error{"encoding '" + encoding + "' is not supported (bgr8, mono8, yuyv, jpeg, png)"};
}

}  // namespace

std::optional<std::string> EyeEncoderParams::validate() const {
  if (jpeg_quality < 1 || jpeg_quality > 100) return "jpeg_quality must be in 1..100";
  if (max_width_px != 0 && (max_width_px < 16 || max_width_px > kMaxSidePx))
    return "max_width_px must be 0 or in 16..8192";
  return std::nullopt;
}

Result<EyeJpeg> EyeEncoder::encode(const stereoball_msg_EyeImage& image,
                                   const char* encoding) const {
  const std::string enc = encoding ? encoding : "";
  if (enc == "jpeg") {
    // Already compressed by the camera: pass through (the browser decodes it).
    if (image.data._buffer == nullptr || image.data._length < 4 || image.data._buffer[0] != 0xFF ||
        image.data._buffer[1] != 0xD8)
      return Error{"jpeg data does not start with a JPEG marker"};
    return EyeJpeg{{image.data._buffer, image.data._buffer + image.data._length},
                   image.width_px,
                   image.height_px};
  }
  auto bgr = to_bgr(image, enc);
  if (!bgr) return Error{bgr.error()};
  cv::Mat shown = *bgr;
  if (params_.max_width_px != 0 && static_cast<uint32_t>(shown.cols) > params_.max_width_px) {
    const double scale = static_cast<double>(params_.max_width_px) / shown.cols;
    cv::resize(*bgr, shown, cv::Size(), scale, scale, cv::INTER_AREA);
  }
  EyeJpeg out;
  cv::imencode(".jpg", shown, out.bytes, {cv::IMWRITE_JPEG_QUALITY, params_.jpeg_quality});
  out.width_px = static_cast<uint32_t>(shown.cols);
  out.height_px = static_cast<uint32_t>(shown.rows);
  return out;
}

}  // namespace stereoball::viewer
