#pragma once
// Test support: a BGR image packed as a YUYV camera delivers it (BT.601 limited range, each
// pixel pair sharing the mean of its two chroma values), to feed fake cameras and yuyv frames.

#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace stereoball::testing {

/// The YUYV bytes (Y0 U Y1 V per pixel pair, rows of 2 x width bytes) of an 8-bit BGR image of
/// even width.
inline std::vector<std::uint8_t> yuyv_from_bgr(const cv::Mat& bgr) {
  std::vector<std::uint8_t> out(static_cast<size_t>(bgr.cols) * bgr.rows * 2);
  const auto byte = [](double v) {
    return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
  };
  for (int y = 0; y < bgr.rows; ++y) {
    const cv::Vec3b* row = bgr.ptr<cv::Vec3b>(y);
    std::uint8_t* q = &out[static_cast<size_t>(y) * bgr.cols * 2];
    for (int x = 0; x + 1 < bgr.cols; x += 2, q += 4) {
      double luma[2], cb = 0.0, cr = 0.0;
      for (int i = 0; i < 2; ++i) {
        const double b = row[x + i][0], g = row[x + i][1], r = row[x + i][2];
        luma[i] = 16.0 + (65.481 * r + 128.553 * g + 24.966 * b) / 255.0;
        cb += (-37.797 * r - 74.203 * g + 112.0 * b) / 510.0;
        cr += (112.0 * r - 93.786 * g - 18.214 * b) / 510.0;
      }
      q[0] = byte(luma[0]);
      q[1] = byte(128.0 + cb);
      q[2] = byte(luma[1]);
      q[3] = byte(128.0 + cr);
    }
  }
  return out;
}

}  // namespace stereoball::testing
