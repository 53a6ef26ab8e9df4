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

/// The values jpeg_chroma accepts: "444" (colour at full resolution), "422" (half the columns,
/// what most USB MJPEG cameras send), "420" (half the columns and rows).
const std::vector<std::string>& jpeg_chroma_choices();

/// How a publisher encodes the eyes of its stereo frames. An aggregate ({encoding, quality}):
/// frame_codec_fields() takes its defaults from here.
struct FrameCodecParams {
  std::string frame_encoding = "raw";  ///< "raw", "jpeg" (lossy) or "png" (lossless)
  int jpeg_quality = 90;               ///< 1 (smallest) .. 100 (closest to raw)
  std::string jpeg_chroma = "444";     ///< colour resolution of JPEG eyes: 444, 422 or 420
  /// stereo/preview (preview_encoder.hpp), made only while a viewer reads it: eyes scaled to
  /// at most this width; 0 = never offer a preview.
  int preview_max_width_px = 640;
  int preview_jpeg_quality = 75;  ///< 1..100; 75 with 4:2:0 is what the viewer always showed

  /// Success, or the field out of its range, naming key and allowed values.
  Status validate() const;
  /// True when the eyes are compressed ("jpeg" or "png").
  bool compressed() const { return frame_encoding == "jpeg" || frame_encoding == "png"; }
};

/// frame_encoding, jpeg_quality, jpeg_chroma and the preview fields, as the camera_server and
/// simulator files hold them.
const params::FieldTable<FrameCodecParams>& frame_codec_fields();

/// zlib level of PNG frames: 1 = fastest; PNG is lossless at every level, higher levels only
/// trade encode time (several times longer) for a few percent fewer bytes.
inline constexpr int kPngCompressionLevel = 1;

/// Encodes one eye of a stereo frame, reusing its output buffer from frame to frame. JPEG
/// (libjpeg) keeps the colour at the resolution jpeg_chroma asks: 444 by default, because
/// halving the chroma blurs the colour edges the ball detector works on (deploy/README.md);
/// 422/420 cost fewer bytes and less encode and decode work.
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
