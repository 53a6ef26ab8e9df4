#pragma once
// Compressed stereo stream: how a frame publisher (camera_server, simulator) puts each eye on
// the wire, and the encoder. Contract of compressed frames (deploy/README.md): StereoFrame
// encoding "jpeg" or "png" for both eyes, each EyeImage.data one complete JPEG/PNG stream,
// width_px/height_px the decoded size, step_bytes 0.

#include <opencv2/core.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/params/field_table.hpp"
#include "common/util/result.hpp"

namespace stereoball::stereo {

/// The values frame_encoding accepts: "raw" (pixels as they are), "jpeg", "png".
const std::vector<std::string>& frame_encoding_choices();

/// How a publisher encodes the eyes of its stereo frames. An aggregate ({encoding, quality}):
/// frame_codec_fields() takes its defaults from here.
struct FrameCodecParams {
  std::string frame_encoding = "raw";  ///< "raw", "jpeg" (lossy) or "png" (lossless)
  int jpeg_quality = 90;               ///< 1 (smallest) .. 100 (closest to raw)
  /// stereo/preview (preview_encoder.hpp), made only while a viewer reads it: eyes scaled to
  /// at most this width; 0 = never offer a preview.
  int preview_max_width_px = 640;
  int preview_jpeg_quality = 75;  ///< 1..100; 75 with 4:2:0 is what the viewer always showed

  /// Success, or the field out of its range, naming key and allowed values.
  Status validate() const;
  /// True when the eyes are compressed ("jpeg" or "png").
  bool compressed() const { return frame_encoding == "jpeg" || frame_encoding == "png"; }
};

/// frame_encoding, jpeg_quality and the preview fields, as the camera_server and simulator
/// files hold them.
const params::FieldTable<FrameCodecParams>& frame_codec_fields();

/// zlib level of PNG frames: 1 = fastest; PNG is lossless at every level, higher levels only
/// trade encode time (several times longer) for a few percent fewer bytes.
inline constexpr int kPngCompressionLevel = 1;

/// Encodes one eye of a stereo frame, reusing its output buffer from frame to frame. JPEG keeps
/// the colour at full resolution (4:4:4, libjpeg) rather than OpenCV's 4:2:0: halving the
/// chroma blurs the red-channel edges the ball detector works on (85 % -> 55 % detections on
/// the textured ball at every quality, deploy/README.md).
class EyeEncoder {
 public:
  /// params must be valid and compressed().
  explicit EyeEncoder(const FrameCodecParams& params);

  /// Compresses an 8-bit grey or BGR image into bytes(); an error names the problem.
  Status encode(const cv::Mat& image);
  /// The complete JPEG/PNG stream of the last successful encode().
  const std::vector<uint8_t>& bytes() const { return bytes_; }

 private:
  Status encode_jpeg(const cv::Mat& image);

  FrameCodecParams params_;
  std::vector<uint8_t> bytes_;
};

}  // namespace stereoball::stereo
