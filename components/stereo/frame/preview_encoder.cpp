#include "stereo/frame/preview_encoder.hpp"

#include <turbojpeg.h>

#include <opencv2/imgproc.hpp>

#include <string>

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
  cv::cvtColor(view, bgr, cv::COLOR_YUV2BGR_YUYV);
  return bgr;
}

}  // namespace

PreviewEncoder::PreviewEncoder(const FrameCodecParams& params) : params_(params) {}

PreviewEncoder::~PreviewEncoder() {
  if (compressor_) tjDestroy(compressor_);
}

Result<EyeView> PreviewEncoder::encode_eye(const char* name, const EyeView& eye,
                                           const std::string& encoding, std::vector<uint8_t>& out) {
  auto pixels = pixels_of(eye, encoding, bgr_);
  if (!pixels) return Error{std::string(name) + " eye: " + pixels.error()};
  cv::Mat shown = *pixels;
  if (shown.cols > params_.preview_max_width_px) {
    // INTER_AREA: a scaled-down picture without the aliasing of nearest/linear sampling.
    const double scale = static_cast<double>(params_.preview_max_width_px) / shown.cols;
    cv::resize(*pixels, scaled_, cv::Size(), scale, scale, cv::INTER_AREA);
    shown = scaled_;
  }
  if (!compressor_) compressor_ = tjInitCompress();
  if (!compressor_) return Error{std::string("cannot start the JPEG encoder: ") + tjGetErrorStr()};
  const bool grey = shown.channels() == 1;
  const int subsampling = grey ? TJSAMP_GRAY : TJSAMP_420;
  // Grown to the worst case once, never shrunk: no allocation or clearing per frame.
  const size_t worst = tjBufSize(shown.cols, shown.rows, subsampling);
  if (out.size() < worst) out.resize(worst);
  unsigned char* dst = out.data();
  unsigned long size = out.size();
  // TJFLAG_NOREALLOC: the worst-case buffer is ours and reused from frame to frame.
  if (tjCompress2(compressor_, shown.data, shown.cols, static_cast<int>(shown.step), shown.rows,
                  grey ? TJPF_GRAY : TJPF_BGR, &dst, &size, subsampling,
                  params_.preview_jpeg_quality, TJFLAG_NOREALLOC | TJFLAG_FASTDCT) != 0)
    return Error{std::string(name) + " eye: JPEG encoding failed: " + tjGetErrorStr2(compressor_)};
  EyeView v;
  v.capture_stamp_ns = eye.capture_stamp_ns;
  v.width_px = static_cast<uint32_t>(shown.cols);
  v.height_px = static_cast<uint32_t>(shown.rows);
  v.step_bytes = 0;
  v.data = out.data();
  v.bytes = size;
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
