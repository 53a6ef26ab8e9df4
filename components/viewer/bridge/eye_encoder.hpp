#pragma once
// One eye of a StereoFrame as a JPEG for people to look at: raw encodings are encoded at the
// chosen quality (and optionally scaled down), JPEG eyes pass through unchanged. Encoding uses
// libjpeg-turbo's TurboJPEG API (BGR in directly, 4:2:0 chroma as usual for viewing, the fast
// integer DCT, no allocation per frame): the viewer's main cost. Every size is checked against
// the configured input limit before anything is decoded or encoded (compressed eyes from their
// header, as ball_detector does).

#include <opencv2/core.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/util/result.hpp"
#include "stereo/image/image_decode.hpp"
#include "stereo/image/viewing_jpeg.hpp"
#include "stereoball.h"

namespace stereoball::viewer {

/// Encoder settings.
struct EyeEncoderParams {
  int jpeg_quality = 75;        ///< 1..100
  uint32_t max_width_px = 640;  ///< wider images are scaled down to this width (0 = never)
  /// Largest eye accepted (raw size fields, JPEG/PNG headers); larger ones are refused.
  uint32_t max_input_width_px = 4096;
  uint32_t max_input_height_px = 4096;
  /// Success, or an error naming the bad field and its allowed range.
  Status validate() const;
};

/// A JPEG of one eye with the size it shows and the size of the eye it was made from (the
/// detections' pixel coordinates are in the latter).
struct EyeJpeg {
  std::vector<uint8_t> bytes;
  uint32_t width_px = 0;
  uint32_t height_px = 0;
  uint32_t source_width_px = 0;
  uint32_t source_height_px = 0;
};

class EyeEncoder {
 public:
  explicit EyeEncoder(const EyeEncoderParams& params);
  /// JPEG of image (encoding as in StereoFrame.encoding); error names the problem. Reuses the
  /// encoder's compressor and scratch buffer from call to call: one encoder per thread.
  Result<EyeJpeg> encode(const stereoball_msg_EyeImage& image, const char* encoding);
  /// One eye of a stereo/preview (a JPEG made for viewing by the frame's publisher): passed
  /// through, or decoded and scaled down when it is wider than max_width_px; the size the
  /// detections refer to is source_width_px x source_height_px of the preview.
  Result<EyeJpeg> encode_preview(const stereoball_msg_EyeImage& image, uint32_t source_width_px,
                                 uint32_t source_height_px);

 private:
  Result<cv::Mat> to_bgr(const stereoball_msg_EyeImage& image, const std::string& encoding);
  Result<EyeJpeg> pass_through(const stereoball_msg_EyeImage& image);
  // The bytes of a PNG or JPEG eye decoded into decoded_, after its header was checked.
  Result<cv::Mat> decode(const stereoball_msg_EyeImage& image, stereo::ImageCodec codec);
  // bgr scaled to max_width_px and encoded (stereo/image/viewing_jpeg).
  Result<EyeJpeg> compress(const cv::Mat& bgr);
  EyeEncoderParams params_;
  cv::Mat decoded_;                  // PNG and yuyv eyes are decoded into this (reused)
  stereo::ViewingJpegEncoder jpeg_;  // movable: EyeEncoder keeps its default moves
};

}  // namespace stereoball::viewer
