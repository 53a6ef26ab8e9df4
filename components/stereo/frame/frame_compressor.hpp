#pragma once
// Turns a decoded outgoing frame (bgr8/mono8) into a compressed one (jpeg/png per eye).

#include "stereo/frame/frame_codec.hpp"
#include "stereo/frame/frame_view.hpp"

namespace stereoball::stereo {

/// Compresses both eyes of decoded frame views, reusing its buffers.
class FrameCompressor {
 public:
  /// params must be valid and compressed().
  explicit FrameCompressor(const FrameCodecParams& params);

  /// The compressed view of view: encoding "jpeg"/"png", step_bytes 0, the decoded size, the
  /// same seq and stamps; points into this compressor until the next step. Fails (naming the
  /// eye) for encodings other than bgr8/mono8 or when the encoder fails.
  Result<FrameView> step(const FrameView& view);

 private:
  FrameCodecParams params_;
  EyeEncoder left_;
  EyeEncoder right_;
};

}  // namespace stereoball::stereo
