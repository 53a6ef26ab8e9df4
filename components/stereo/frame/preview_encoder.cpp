#include "stereo/frame/preview_encoder.hpp"

#include <string>

#include "stereo/frame/eye_pixels.hpp"

namespace stereoball::stereo {

Result<EyeView> PreviewEncoder::encode_eye(const char* name, const EyeView& eye,
                                           const std::string& encoding,
                                           ViewingJpegEncoder& encoder) {
  auto pixels = eye_pixels(eye, encoding, bgr_);
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
