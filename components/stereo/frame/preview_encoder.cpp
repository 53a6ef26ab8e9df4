#include "stereo/frame/preview_encoder.hpp"

#include <span>
#include <string>

#include "stereo/image/yuyv_convert.hpp"

namespace stereoball::stereo {
namespace {

// The pixels of a raw eye without a copy (bgr8, mono8; yuyv converted into bgr), sizes checked
// against the bytes the view holds.
Result<cv::Mat> pixels_of(const EyeView& eye, const std::string& encoding, cv::Mat& bgr) {
  if (eye.data == nullptr || eye.width_px == 0 || eye.height_px == 0) return Error{"empty image"};
  const int channels = encoding == "bgr8"    ? 3
                       : encoding == "mono8" ? 1
                       : encoding == "yuyv"  ? 2
                                             : 0;
  if (channels == 0)
    return Error{"cannot make a preview of \"" + encoding + "\" frames (bgr8, mono8, yuyv)"};
  if (eye.step_bytes < uint64_t{eye.width_px} * static_cast<uint32_t>(channels) ||
      eye.bytes < uint64_t{eye.step_bytes} * eye.height_px)
    return Error{"image data has " + std::to_string(eye.bytes) + " bytes for " +
                 std::to_string(eye.width_px) + "x" + std::to_string(eye.height_px) +
                 " with step " + std::to_string(eye.step_bytes)};
  const cv::Mat view(static_cast<int>(eye.height_px), static_cast<int>(eye.width_px),
                     CV_8UC(channels), const_cast<uint8_t*>(eye.data), eye.step_bytes);
  if (channels != 2) return view;
  if (eye.width_px % 2 != 0) return Error{"yuyv width " + std::to_string(eye.width_px) + " is odd"};
  // The conversion the frame decoder and camera_server use: the preview shows what they see.
  const Status converted = yuyv_to_bgr(std::span<const uint8_t>(eye.data, eye.bytes), view.cols,
                                       view.rows, static_cast<int>(eye.step_bytes), bgr);
  if (!converted) return Error{converted.error()};
  return bgr;
}

}  // namespace

Result<EyeView> PreviewEncoder::encode_eye(const char* name, const EyeView& eye,
                                           const std::string& encoding,
                                           ViewingJpegEncoder& encoder) {
  auto pixels = pixels_of(eye, encoding, bgr_);
  if (!pixels) return Error{std::string(name) + " eye: " + pixels.error()};
  const auto jpeg =
      encoder.encode(*pixels, params_.preview_max_width_px, params_.preview_jpeg_quality);
  if (!jpeg) return Error{std::string(name) + " eye: " + jpeg.error()};
  EyeView v;
  v.capture_stamp_ns = eye.capture_stamp_ns;
  v.width_px = static_cast<uint32_t>(jpeg->width_px);
  v.height_px = static_cast<uint32_t>(jpeg->height_px);
  v.step_bytes = 0;
  v.data = jpeg->bytes.data();
  v.bytes = jpeg->bytes.size();
  return v;
}

Result<PreviewView> PreviewEncoder::step(const FrameView& view) {
  if (view.left.width_px != view.right.width_px || view.left.height_px != view.right.height_px)
    return Error{"the eyes differ in size"};
  auto left = encode_eye("left", view.left, view.encoding, left_);
  if (!left) return Error{left.error()};
  auto right = encode_eye("right", view.right, view.encoding, right_);
  if (!right) return Error{right.error()};
  PreviewView out;
  out.view = view;
  out.view.encoding = "jpeg";
  out.view.left = *left;
  out.view.right = *right;
  out.source_width_px = view.left.width_px;
  out.source_height_px = view.left.height_px;
  return out;
}

}  // namespace stereoball::stereo
