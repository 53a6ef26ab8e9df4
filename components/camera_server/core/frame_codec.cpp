#include "camera_server/core/frame_codec.hpp"

#include <opencv2/imgcodecs.hpp>

namespace stereoball::camera_server {

const std::vector<std::string>& frame_encoding_choices() {
  static const std::vector<std::string> kChoices{"raw", "jpeg", "png"};
  return kChoices;
}

std::optional<std::string> FrameCodecParams::validate() const {
  if (frame_encoding != "raw" && !compressed()) {
    return "frame_encoding must be \"raw\", \"jpeg\" or \"png\", got \"" + frame_encoding + "\"";
  }
  if (jpeg_quality < 1 || jpeg_quality > 100) {
    return "jpeg_quality must be in [1, 100], got " + std::to_string(jpeg_quality);
  }
  return std::nullopt;
}

EyeEncoder::EyeEncoder(const FrameCodecParams& params) : params_(params) {
  if (params_.frame_encoding == "jpeg") {
    flags_ = {cv::IMWRITE_JPEG_QUALITY, params_.jpeg_quality};
  } else {
    flags_ = {cv::IMWRITE_PNG_COMPRESSION, kPngCompressionLevel};
  }
}

std::optional<std::string> EyeEncoder::encode(const cv::Mat& image) {
  if (image.empty()) return "cannot " + params_.frame_encoding + "-encode an empty image";
  if (image.type() != CV_8UC1 && image.type() != CV_8UC3) {
    return "cannot " + params_.frame_encoding +
           "-encode this image: only 8-bit grey or BGR images are supported";
  }
  const char* extension = params_.frame_encoding == "jpeg" ? ".jpg" : ".png";
  bool ok = false;
  try {
    ok = cv::imencode(extension, image, bytes_, flags_);
  } catch (const cv::Exception& e) {
    return params_.frame_encoding + " encoding failed: " + e.what();
  }
  if (!ok || bytes_.empty()) return params_.frame_encoding + " encoding failed";
  return std::nullopt;
}

}  // namespace stereoball::camera_server
