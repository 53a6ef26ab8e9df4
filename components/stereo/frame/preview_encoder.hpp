#pragma once
// The picture of stereo/preview (what `stereoball view` shows): both eyes of an outgoing frame
// as JPEGs for people, scaled to at most preview_max_width_px, 4:2:0 chroma and the fast
// integer DCT (libjpeg-turbo's TurboJPEG API, BGR in directly). Not the detector's format:
// stereo/frame's own jpeg keeps 4:4:4 (frame_codec.hpp) because the detector needs the chroma.

#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

#include "common/util/result.hpp"
#include "stereo/frame/frame_codec.hpp"
#include "stereo/frame/frame_view.hpp"

namespace stereoball::stereo {

/// A preview: the compressed view (encoding "jpeg", eyes at the preview size, the frame's seq
/// and stamps) and the size of the eyes it was made from (the pixels detections refer to).
struct PreviewView {
  FrameView view;
  uint32_t source_width_px = 0;
  uint32_t source_height_px = 0;
};

/// Encodes previews, reusing its TurboJPEG handle and buffers: one encoder per thread.
class PreviewEncoder {
 public:
  /// params must be valid (preview_jpeg_quality, preview_max_width_px > 0).
  explicit PreviewEncoder(const FrameCodecParams& params);
  ~PreviewEncoder();
  PreviewEncoder(const PreviewEncoder&) = delete;
  PreviewEncoder& operator=(const PreviewEncoder&) = delete;

  /// The preview of a bgr8, mono8 or yuyv view; points into this encoder until the next step.
  /// Fails (naming the eye) for other encodings, eyes of different sizes or truncated data.
  Result<PreviewView> step(const FrameView& view);

 private:
  Result<EyeView> encode_eye(const char* name, const EyeView& eye, const std::string& encoding,
                             std::vector<uint8_t>& out);

  FrameCodecParams params_;
  void* compressor_ = nullptr;  // tjhandle, created on first use
  cv::Mat bgr_;                 // yuyv eyes are converted into this
  cv::Mat scaled_;              // eyes wider than the preview are scaled into this
  std::vector<uint8_t> left_, right_;
};

}  // namespace stereoball::stereo
