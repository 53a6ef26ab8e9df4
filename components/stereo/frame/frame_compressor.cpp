#include "stereo/frame/frame_compressor.hpp"

namespace stereoball::stereo {
namespace {

Result<EyeView> compress_eye(const char* name, const EyeView& eye, const std::string& encoding,
                             EyeEncoder& encoder) {
  const cv::Mat image = image_of(eye, encoding);
  if (image.empty()) {
    return Error{std::string(name) + " eye: cannot compress \"" + encoding +
                 "\" frames, only bgr8 or mono8"};
  }
  if (auto st = encoder.encode(image); !st) return Error{std::string(name) + " eye: " + st.error()};
  EyeView out = eye;
  out.step_bytes = 0;
  out.data = encoder.bytes().data();
  out.bytes = encoder.bytes().size();
  return out;
}

}  // namespace

FrameCompressor::FrameCompressor(const FrameCodecParams& params)
    : params_(params), left_(params), right_(params) {}

Result<FrameView> FrameCompressor::step(const FrameView& view) {
  auto left = compress_eye("left", view.left, view.encoding, left_);
  if (!left) return Error{left.error()};
  auto right = compress_eye("right", view.right, view.encoding, right_);
  if (!right) return Error{right.error()};
  FrameView out = view;
  out.encoding = params_.frame_encoding;
  out.left = *left;
  out.right = *right;
  return out;
}

}  // namespace stereoball::stereo
