#pragma once
// The picture of stereo/preview (what `stereoball view` shows): both eyes of an outgoing frame
// as JPEGs for people (stereo/image/viewing_jpeg), scaled to at most preview_max_width_px. Not
// the detector's format:
// stereo/frame's own jpeg keeps 4:4:4 (frame_codec.hpp) because the detector needs the chroma.

#include <opencv2/core.hpp>

#include <cstdint>

#include "common/util/result.hpp"
#include "stereo/frame/frame_codec.hpp"
#include "stereo/frame/frame_view.hpp"
#include "stereo/image/viewing_jpeg.hpp"

namespace stereoball::stereo {

/// A preview: the compressed view (encoding "jpeg", eyes at the preview size, the frame's seq
/// and stamps) and the size of the eyes it was made from (the pixels detections refer to).
struct PreviewView {
  FrameView view;
  uint32_t source_width_px = 0;
  uint32_t source_height_px = 0;
};

/// Encodes previews, reusing its encoders and buffers: one PreviewEncoder per thread.
class PreviewEncoder {
 public:
  /// params must be valid (preview_jpeg_quality, preview_max_width_px > 0).
  explicit PreviewEncoder(const FrameCodecParams& params) : params_(params) {}

  /// The preview of a bgr8, mono8 or yuyv view; points into this encoder until the next step.
  /// Fails (naming the eye) for other encodings, eyes of different sizes or truncated data.
  Result<PreviewView> step(const FrameView& view);

 private:
  Result<EyeView> encode_eye(const char* name, const EyeView& eye, const std::string& encoding,
                             ViewingJpegEncoder& encoder);

  FrameCodecParams params_;
  cv::Mat bgr_;  // yuyv eyes are converted into this
  // One per eye: each holds its eye's bytes until the next step.
  ViewingJpegEncoder left_, right_;
};

}  // namespace stereoball::stereo
