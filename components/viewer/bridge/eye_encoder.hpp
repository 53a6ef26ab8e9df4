#pragma once
// One eye of a StereoFrame as a JPEG for people to look at: raw encodings are encoded at the
// chosen quality (and optionally scaled down), JPEG eyes pass through unchanged.

#include <cstdint>
#include <string>
#include <vector>

#include "common/util/result.hpp"
#include "stereoball.h"

namespace stereoball::viewer {

/// Encoder settings.
struct EyeEncoderParams {
  int jpeg_quality = 75;        ///< 1..100
  uint32_t max_width_px = 640;  ///< wider images are scaled down to this width (0 = never)
  /// nullopt when valid, else a message naming the bad field and its allowed range.
  std::optional<std::string> validate() const;
};

/// A JPEG of one eye with the size it shows.
struct EyeJpeg {
  std::vector<uint8_t> bytes;
  uint32_t width_px = 0;
  uint32_t height_px = 0;
};

class EyeEncoder {
 public:
  explicit EyeEncoder(const EyeEncoderParams& params) : params_(params) {}
  /// JPEG of image (encoding as in StereoFrame.encoding); error names the problem.
  Result<EyeJpeg> encode(const stereoball_msg_EyeImage& image, const char* encoding) const;

 private:
  EyeEncoderParams params_;
};

}  // namespace stereoball::viewer
