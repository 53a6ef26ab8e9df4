#pragma once
// One eye of a StereoFrame as a JPEG for people to look at: raw encodings are encoded at the
// chosen quality (and optionally scaled down), JPEG eyes pass through unchanged. Encoding uses
// libjpeg-turbo's TurboJPEG API (BGR in directly, 4:2:0 chroma as usual for viewing, the fast
// integer DCT, no allocation per frame): the viewer's main cost.

#include <opencv2/core.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/util/result.hpp"
#include "stereoball.h"

namespace stereoball::viewer {

/// Encoder settings.
struct EyeEncoderParams {
  int jpeg_quality = 75;        ///< 1..100
  uint32_t max_width_px = 640;  ///< wider images are scaled down to this width (0 = never)
  /// Success, or an error naming the bad field and its allowed range.
  Status validate() const;
};

/// A JPEG of one eye with the size it shows.
struct EyeJpeg {
  std::vector<uint8_t> bytes;
  uint32_t width_px = 0;
  uint32_t height_px = 0;
};

class EyeEncoder {
 public:
  explicit EyeEncoder(const EyeEncoderParams& params);
  ~EyeEncoder();
  EyeEncoder(EyeEncoder&&) noexcept;
  EyeEncoder& operator=(EyeEncoder&&) noexcept;
  /// JPEG of image (encoding as in StereoFrame.encoding); error names the problem. Reuses the
  /// encoder's compressor and scratch buffer from call to call: one encoder per thread.
  Result<EyeJpeg> encode(const stereoball_msg_EyeImage& image, const char* encoding);

 private:
  Result<EyeJpeg> compress(const cv::Mat& shown);
  EyeEncoderParams params_;
  void* compressor_ = nullptr;          // TurboJPEG handle (tjhandle), created on first use
  std::vector<unsigned char> scratch_;  // worst-case output size of the last image shape
};

}  // namespace stereoball::viewer
