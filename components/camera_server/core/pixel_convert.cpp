#include "camera_server/core/pixel_convert.hpp"

#include <algorithm>
#include <array>
#include <string>

#include <opencv2/imgcodecs.hpp>

namespace stereoball::camera_server {
namespace {

// BT.601 limited-range coefficients (1.164, 1.596, -0.391, -0.813, 2.018) in 20-bit fixed point.
constexpr int kShift = 20;
constexpr int kCy = 1220542;
constexpr int kCvr = 1673527;
constexpr int kCug = -409993;
constexpr int kCvg = -852492;
constexpr int kCub = 2116026;
constexpr int kHalf = 1 << (kShift - 1);

// Every per-sample product precomputed once: the inner loop is adds, shifts and clamps.
struct YuvTables {
  std::array<int32_t, 256> y{};
  std::array<int32_t, 256> rv{};
  std::array<int32_t, 256> gu{};
  std::array<int32_t, 256> gv{};
  std::array<int32_t, 256> bu{};
  YuvTables() {
    for (int i = 0; i < 256; ++i) {
      y[i] = std::max(0, i - 16) * kCy;
      rv[i] = kHalf + kCvr * (i - 128);
      gu[i] = kCug * (i - 128);
      gv[i] = kHalf + kCvg * (i - 128);
      bu[i] = kHalf + kCub * (i - 128);
    }
  }
};

const YuvTables& tables() {
  static const YuvTables t;
  return t;
}

inline uint8_t clamp_shift(int32_t v) {
  v >>= kShift;
  return static_cast<uint8_t>(v < 0 ? 0 : (v > 255 ? 255 : v));
}

void convert_row(const uint8_t* src, uint8_t* dst, int width_px, const YuvTables& t) {
  for (int x = 0; x < width_px; x += 2, src += 4, dst += 6) {
    const int32_t ruv = t.rv[src[3]];
    const int32_t guv = t.gu[src[1]] + t.gv[src[3]];
    const int32_t buv = t.bu[src[1]];
    const int32_t y0 = t.y[src[0]];
    const int32_t y1 = t.y[src[2]];
    dst[0] = clamp_shift(y0 + buv);
    dst[1] = clamp_shift(y0 + guv);
    dst[2] = clamp_shift(y0 + ruv);
    dst[3] = clamp_shift(y1 + buv);
    dst[4] = clamp_shift(y1 + guv);
    dst[5] = clamp_shift(y1 + ruv);
  }
}

std::string size_text(int w, int h) {
  return std::to_string(w) + "x" + std::to_string(h);
}

}  // namespace

Status yuyv_to_bgr_into(std::span<const uint8_t> yuyv, int width_px, int height_px, int step_bytes,
                        uint8_t* dst, int dst_step_bytes) {
  if (width_px <= 0 || height_px <= 0 || width_px % 2 != 0) {
    return fail("YUYV frame size " + size_text(width_px, height_px) +
                " is invalid (width must be even and > 0)");
  }
  if (step_bytes < 2 * width_px || dst_step_bytes < 3 * width_px) {
    return fail("YUYV row pitch " + std::to_string(step_bytes) + " is smaller than 2 x width " +
                std::to_string(width_px));
  }
  const size_t needed = static_cast<size_t>(step_bytes) * (height_px - 1) + 2 * width_px;
  if (yuyv.size() < needed) {
    return fail("YUYV frame is truncated: " + std::to_string(yuyv.size()) + " bytes, " +
                size_text(width_px, height_px) + " needs " + std::to_string(needed));
  }
  const YuvTables& t = tables();
  for (int row = 0; row < height_px; ++row) {
    convert_row(yuyv.data() + static_cast<size_t>(row) * step_bytes,
                dst + static_cast<size_t>(row) * dst_step_bytes, width_px, t);
  }
  return Ok{};
}

Status yuyv_to_bgr(std::span<const uint8_t> yuyv, int width_px, int height_px, int step_bytes,
                   cv::Mat& bgr) {
  if (width_px > 0 && height_px > 0) bgr.create(height_px, width_px, CV_8UC3);
  return yuyv_to_bgr_into(yuyv, width_px, height_px, step_bytes, bgr.data,
                          static_cast<int>(bgr.step));
}

Status mjpeg_to_bgr(std::span<const uint8_t> jpeg, int width_px, int height_px, cv::Mat& bgr) {
  // SOI marker: anything else is not a JPEG (imdecode would try other codecs).
  if (jpeg.size() < 4 || jpeg[0] != 0xFF || jpeg[1] != 0xD8) {
    return fail("MJPEG frame is not a JPEG (" + std::to_string(jpeg.size()) +
                " bytes, no start-of-image marker)");
  }
  const cv::Mat raw(1, static_cast<int>(jpeg.size()), CV_8UC1, const_cast<uint8_t*>(jpeg.data()));
  cv::Mat decoded = cv::imdecode(raw, cv::IMREAD_COLOR);
  if (decoded.empty()) {
    return fail("MJPEG frame could not be decoded (" + std::to_string(jpeg.size()) +
                " bytes, corrupt or truncated)");
  }
  if ((width_px != 0 || height_px != 0) &&
      (decoded.cols != width_px || decoded.rows != height_px)) {
    return fail("MJPEG frame is " + size_text(decoded.cols, decoded.rows) + ", expected " +
                size_text(width_px, height_px));
  }
  bgr = std::move(decoded);
  return Ok{};
}

}  // namespace stereoball::camera_server
