#pragma once
// JPEGs for people to look at (stereo/preview on the robot, the viewer's eyes): scaled down to
// a width without aliasing (INTER_AREA), 4:2:0 chroma and the fast integer DCT through
// libjpeg-turbo's TurboJPEG API (BGR in directly). At viewing qualities (<= 90) the fast DCT
// differs from the exact one by less than the quantisation itself, and it is the cheaper one.

#include <opencv2/core.hpp>

#include <cstdint>
#include <span>
#include <vector>

#include "common/util/result.hpp"

namespace stereoball::stereo {

/// One encoded picture: bytes valid until the encoder's next call, and the size it shows.
struct ViewingJpeg {
  std::span<const uint8_t> bytes;
  int width_px = 0;
  int height_px = 0;
};

/// Reuses its TurboJPEG handle and buffers from call to call: one encoder per thread.
class ViewingJpegEncoder {
 public:
  ViewingJpegEncoder() = default;
  ~ViewingJpegEncoder();
  ViewingJpegEncoder(ViewingJpegEncoder&& other) noexcept;
  ViewingJpegEncoder& operator=(ViewingJpegEncoder&& other) noexcept;
  ViewingJpegEncoder(const ViewingJpegEncoder&) = delete;
  ViewingJpegEncoder& operator=(const ViewingJpegEncoder&) = delete;

  /// image (CV_8UC3 BGR or CV_8UC1 grey) scaled down to at most max_width_px (0 = never) and
  /// compressed at quality (1..100); error names the problem.
  Result<ViewingJpeg> encode(const cv::Mat& image, int max_width_px, int quality);

 private:
  void* compressor_ = nullptr;  // tjhandle, created on first use
  cv::Mat scaled_;
  std::vector<uint8_t> out_;  // grown to the worst case once, never shrunk
};

}  // namespace stereoball::stereo
