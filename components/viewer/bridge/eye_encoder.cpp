#include "viewer/bridge/eye_encoder.hpp"

#include <cstring>
#include <span>
#include <utility>

#include "stereo/image/image_decode.hpp"
#include "stereo/image/yuyv_convert.hpp"

namespace stereoball::viewer {
namespace {

constexpr uint32_t kMaxSidePx = 16384;  // the largest limit a user may configure

std::string dims(uint64_t w, uint64_t h) {
  return std::to_string(w) + "x" + std::to_string(h);
}

// The raw pixels of image as a Mat over the sample's own bytes (no copy), sizes checked first.
Result<cv::Mat> raw_view(const stereoball_msg_EyeImage& image, int type, uint32_t bytes_per_px) {
  if (image.step_bytes < uint64_t{image.width_px} * bytes_per_px)
    return Error{"step_bytes " + std::to_string(image.step_bytes) + " is smaller than a row"};
  const uint64_t need = uint64_t{image.step_bytes} * image.height_px;
  if (image.data._buffer == nullptr || image.data._length < need)
    return Error{"image data has " + std::to_string(image.data._length) + " bytes, expected " +
                 std::to_string(need) + " (truncated)"};
  return cv::Mat(static_cast<int>(image.height_px), static_cast<int>(image.width_px), type,
                 image.data._buffer, image.step_bytes);
}

std::span<const uint8_t> bytes_of(const stereoball_msg_EyeImage& image) {
  if (image.data._buffer == nullptr) return {};
  return {image.data._buffer, image.data._length};
}

}  // namespace

Status EyeEncoderParams::validate() const {
  if (jpeg_quality < 1 || jpeg_quality > 100) return Error{"jpeg_quality must be in 1..100"};
  if (max_width_px != 0 && (max_width_px < 16 || max_width_px > kMaxSidePx))
    return Error{"max_width_px must be 0 or in 16..16384"};
  if (max_input_width_px < 16 || max_input_width_px > kMaxSidePx || max_input_height_px < 16 ||
      max_input_height_px > kMaxSidePx)
    return Error{"max_input_width_px and max_input_height_px must be in 16..16384"};
  return {};
}

EyeEncoder::EyeEncoder(const EyeEncoderParams& params) : params_(params) {}

Result<cv::Mat> EyeEncoder::to_bgr(const stereoball_msg_EyeImage& image,
                                   const std::string& encoding) {
  if (encoding == "bgr8") return raw_view(image, CV_8UC3, 3);
  if (encoding == "mono8") return raw_view(image, CV_8UC1, 1);
  if (encoding == "yuyv") {
    if (image.width_px % 2 != 0)
      return Error{"yuyv width " + std::to_string(image.width_px) + " is odd"};
    auto view = raw_view(image, CV_8UC2, 2);
    if (!view) return Error{view.error()};
    // The conversion camera_server's bgr8 comes from: the viewer shows what the detector sees.
    if (auto st = stereo::yuyv_to_bgr(bytes_of(image), view->cols, view->rows,
                                      static_cast<int>(image.step_bytes), decoded_);
        !st)
      return Error{st.error()};
    return decoded_;
  }
  if (encoding == "png") return decode(image, stereo::ImageCodec::kPng);
  return Error{"encoding '" + encoding + "' is not supported (bgr8, mono8, yuyv, jpeg, png)"};
}

Result<cv::Mat> EyeEncoder::decode(const stereoball_msg_EyeImage& image, stereo::ImageCodec codec) {
  // As ball_detector does: the header decides how much memory decoding takes, so it is read
  // and checked against the limit before any pixel is decoded.
  const std::string name = stereo::codec_name(codec);
  const auto bytes = bytes_of(image);
  if (bytes.empty()) return Error{name + " data is empty"};
  const auto header = stereo::read_image_header(bytes);
  if (!header) return Error{name + " data: " + header.error()};
  if (header->codec != codec)
    return Error{std::string(stereo::codec_name(header->codec)) + " data in a " + name + " frame"};
  if (auto st = stereo::check_within(*header, {static_cast<int>(params_.max_input_width_px),
                                               static_cast<int>(params_.max_input_height_px)});
      !st)
    return Error{st.error()};
  if (auto st = stereo::decode_bgr(bytes, *header, decoded_); !st) return Error{st.error()};
  return decoded_;
}

Result<EyeJpeg> EyeEncoder::pass_through(const stereoball_msg_EyeImage& image) {
  // Already compressed by the camera: forwarded as it is (the browser decodes it), after its
  // header was read and checked like any other input.
  const auto bytes = bytes_of(image);
  if (bytes.size() < 4 || bytes[0] != 0xFF || bytes[1] != 0xD8)
    return Error{"jpeg data does not start with a JPEG marker"};
  const auto header = stereo::read_image_header(bytes);
  if (!header) return Error{"jpeg data: " + header.error()};
  if (auto st = stereo::check_within(*header, {static_cast<int>(params_.max_input_width_px),
                                               static_cast<int>(params_.max_input_height_px)});
      !st)
    return Error{st.error()};
  const auto w = static_cast<uint32_t>(header->width_px);
  const auto h = static_cast<uint32_t>(header->height_px);
  return EyeJpeg{{bytes.begin(), bytes.end()}, w, h, w, h};
}

Result<EyeJpeg> EyeEncoder::encode(const stereoball_msg_EyeImage& image, const char* encoding) {
  const std::string enc = encoding ? encoding : "";
  if (enc == "jpeg") return pass_through(image);
  if (enc != "png" &&
      (image.width_px == 0 || image.height_px == 0 || image.width_px > params_.max_input_width_px ||
       image.height_px > params_.max_input_height_px))
    return Error{"image size " + dims(image.width_px, image.height_px) + " is outside 1x1.." +
                 dims(params_.max_input_width_px, params_.max_input_height_px)};
  auto bgr = to_bgr(image, enc);
  if (!bgr) return Error{bgr.error()};
  auto jpeg = compress(*bgr);
  if (!jpeg) return jpeg;
  jpeg->source_width_px = static_cast<uint32_t>(bgr->cols);
  jpeg->source_height_px = static_cast<uint32_t>(bgr->rows);
  return jpeg;
}

Result<EyeJpeg> EyeEncoder::encode_preview(const stereoball_msg_EyeImage& image,
                                           uint32_t source_width_px, uint32_t source_height_px) {
  if (source_width_px == 0 || source_height_px == 0 ||
      source_width_px > params_.max_input_width_px ||
      source_height_px > params_.max_input_height_px)
    return Error{"source size " + dims(source_width_px, source_height_px) + " is outside 1x1.." +
                 dims(params_.max_input_width_px, params_.max_input_height_px)};
  auto jpeg = pass_through(image);
  if (!jpeg) return jpeg;
  if (params_.max_width_px != 0 && jpeg->width_px > params_.max_width_px) {
    // A publisher's preview wider than this viewer shows: made smaller here (decoded, scaled,
    // encoded again), which costs what a raw frame does; preview_max_width_px avoids it.
    auto bgr = decode(image, stereo::ImageCodec::kJpeg);
    if (!bgr) return Error{bgr.error()};
    jpeg = compress(*bgr);
    if (!jpeg) return jpeg;
  }
  jpeg->source_width_px = source_width_px;
  jpeg->source_height_px = source_height_px;
  return jpeg;
}

Result<EyeJpeg> EyeEncoder::compress(const cv::Mat& bgr) {
  const auto jpeg = jpeg_.encode(bgr, static_cast<int>(params_.max_width_px), params_.jpeg_quality);
  if (!jpeg) return Error{jpeg.error()};
  const auto w = static_cast<uint32_t>(jpeg->width_px), h = static_cast<uint32_t>(jpeg->height_px);
  return EyeJpeg{{jpeg->bytes.begin(), jpeg->bytes.end()}, w, h, w, h};
}

}  // namespace stereoball::viewer
