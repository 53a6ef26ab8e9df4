#include "viewer/bridge/eye_encoder.hpp"

#include <turbojpeg.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstring>
#include <utility>

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

Status EyeEncoderParams::validate() const {
  if (jpeg_quality < 1 || jpeg_quality > 100) return Error{"jpeg_quality must be in 1..100"};
  if (max_width_px != 0 && (max_width_px < 16 || max_width_px > kMaxSidePx))
    return Error{"max_width_px must be 0 or in 16..8192"};
  return {};
}

EyeEncoder::EyeEncoder(const EyeEncoderParams& params) : params_(params) {}

EyeEncoder::~EyeEncoder() {
  if (compressor_) tjDestroy(compressor_);
}

EyeEncoder::EyeEncoder(EyeEncoder&& other) noexcept
    : params_(other.params_),
      compressor_(std::exchange(other.compressor_, nullptr)),
      scratch_(std::move(other.scratch_)) {}

EyeEncoder& EyeEncoder::operator=(EyeEncoder&& other) noexcept {
  if (this != &other) {
    if (compressor_) tjDestroy(compressor_);
    params_ = other.params_;
    compressor_ = std::exchange(other.compressor_, nullptr);
    scratch_ = std::move(other.scratch_);
  }
  return *this;
}

Result<EyeJpeg> EyeEncoder::encode(const stereoball_msg_EyeImage& image, const char* encoding) {
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
  return compress(shown);
}

Result<EyeJpeg> EyeEncoder::compress(const cv::Mat& shown) {
  if (!compressor_) compressor_ = tjInitCompress();
  if (!compressor_) return Error{std::string("cannot start the JPEG encoder: ") + tjGetErrorStr()};
  const bool grey = shown.channels() == 1;
  const int subsampling = grey ? TJSAMP_GRAY : TJSAMP_420;
  scratch_.resize(tjBufSize(shown.cols, shown.rows, subsampling));
  unsigned char* out = scratch_.data();
  unsigned long size = scratch_.size();
  // Fast integer DCT: at viewing qualities (<= 90) it differs from the exact one by less than
  // the quantisation itself, and it is the cheaper transform.
  if (tjCompress2(compressor_, shown.data, shown.cols, static_cast<int>(shown.step), shown.rows,
                  grey ? TJPF_GRAY : TJPF_BGR, &out, &size, subsampling, params_.jpeg_quality,
                  TJFLAG_NOREALLOC | TJFLAG_FASTDCT) != 0)
    return Error{std::string("JPEG encoding failed: ") + tjGetErrorStr2(compressor_)};
  return EyeJpeg{
      {out, out + size}, static_cast<uint32_t>(shown.cols), static_cast<uint32_t>(shown.rows)};
}

}  // namespace stereoball::viewer
