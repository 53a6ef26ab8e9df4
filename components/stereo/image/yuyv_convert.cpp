#include "stereo/image/yuyv_convert.hpp"

#include <algorithm>
#include <array>
#include <string>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace stereoball::stereo {
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

void convert_pairs_scalar(const uint8_t* src, uint8_t* dst, int pairs, const YuvTables& t) {
  for (int i = 0; i < pairs; ++i, src += 4, dst += 6) {
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

#if defined(__x86_64__)
// Eight pixel pairs per iteration: each 32-bit lane holds one Y0 U Y1 V group, so unpacking
// is shifts and masks; the arithmetic is the scalar formula in 32-bit lanes (exact), and
// the clamped bytes are packed to 6 per pair and compacted with a byte shuffle.
// Writes up to 4 bytes past the 48 output bytes of each block (caller keeps the slack).
__attribute__((target("avx2"))) void convert_blocks_avx2(const uint8_t* src, uint8_t* dst,
                                                         int blocks) {
  const __m256i mask = _mm256_set1_epi32(0xFF);
  const __m256i c128 = _mm256_set1_epi32(128);
  const __m256i c16 = _mm256_set1_epi32(16);
  const __m256i zero = _mm256_setzero_si256();
  const __m256i c255 = _mm256_set1_epi32(255);
  const __m256i half = _mm256_set1_epi32(kHalf);
  const __m256i cy = _mm256_set1_epi32(kCy);
  const __m256i cvr = _mm256_set1_epi32(kCvr);
  const __m256i cug = _mm256_set1_epi32(kCug);
  const __m256i cvg = _mm256_set1_epi32(kCvg);
  const __m256i cub = _mm256_set1_epi32(kCub);
  // Keeps bytes 0-5 and 8-13 of each 128-bit lane (two pairs of 6 bytes).
  const __m256i compact = _mm256_setr_epi8(0, 1, 2, 3, 4, 5, 8, 9, 10, 11, 12, 13, -1, -1, -1, -1,
                                           0, 1, 2, 3, 4, 5, 8, 9, 10, 11, 12, 13, -1, -1, -1, -1);
  for (int b = 0; b < blocks; ++b, src += 32, dst += 48) {
    const __m256i w = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(src));
    const __m256i y0 = _mm256_max_epi32(_mm256_sub_epi32(_mm256_and_si256(w, mask), c16), zero);
    const __m256i u = _mm256_sub_epi32(_mm256_and_si256(_mm256_srli_epi32(w, 8), mask), c128);
    const __m256i y1 = _mm256_max_epi32(
        _mm256_sub_epi32(_mm256_and_si256(_mm256_srli_epi32(w, 16), mask), c16), zero);
    const __m256i v = _mm256_sub_epi32(_mm256_srli_epi32(w, 24), c128);
    const __m256i yy0 = _mm256_mullo_epi32(y0, cy);
    const __m256i yy1 = _mm256_mullo_epi32(y1, cy);
    const __m256i ruv = _mm256_add_epi32(half, _mm256_mullo_epi32(v, cvr));
    const __m256i guv = _mm256_add_epi32(
        half, _mm256_add_epi32(_mm256_mullo_epi32(v, cvg), _mm256_mullo_epi32(u, cug)));
    const __m256i buv = _mm256_add_epi32(half, _mm256_mullo_epi32(u, cub));
#define SB_CHAN(yy, uv)                                                                         \
  _mm256_min_epi32(_mm256_max_epi32(_mm256_srai_epi32(_mm256_add_epi32(yy, uv), kShift), zero), \
                   c255)
    const __m256i lo =
        _mm256_or_si256(_mm256_or_si256(SB_CHAN(yy0, buv), _mm256_slli_epi32(SB_CHAN(yy0, guv), 8)),
                        _mm256_or_si256(_mm256_slli_epi32(SB_CHAN(yy0, ruv), 16),
                                        _mm256_slli_epi32(SB_CHAN(yy1, buv), 24)));
    const __m256i hi = _mm256_or_si256(SB_CHAN(yy1, guv), _mm256_slli_epi32(SB_CHAN(yy1, ruv), 8));
#undef SB_CHAN
    // Lane 0 holds pairs 0-3, lane 1 pairs 4-7; unpack gives (pair k: lo, hi) 64-bit slots.
    const __m256i a = _mm256_shuffle_epi8(_mm256_unpacklo_epi32(lo, hi), compact);  // 0,1 | 4,5
    const __m256i c = _mm256_shuffle_epi8(_mm256_unpackhi_epi32(lo, hi), compact);  // 2,3 | 6,7
    _mm_storeu_si128(reinterpret_cast<__m128i*>(dst), _mm256_castsi256_si128(a));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(dst + 12), _mm256_castsi256_si128(c));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(dst + 24), _mm256_extracti128_si256(a, 1));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(dst + 36), _mm256_extracti128_si256(c, 1));
  }
}

bool has_avx2() {
  static const bool yes = __builtin_cpu_supports("avx2");
  return yes;
}
#endif

// Converts one row; may write up to 4 bytes past the row when `slack` says that is allowed.
void convert_row(const uint8_t* src, uint8_t* dst, int width_px, bool slack, const YuvTables& t) {
  int pairs = width_px / 2;
#if defined(__x86_64__)
  if (has_avx2()) {
    // Without slack the last block is left to the scalar loop so nothing past the row is written.
    const int blocks = slack ? pairs / 8 : (pairs > 8 ? (pairs - 1) / 8 : 0);
    convert_blocks_avx2(src, dst, blocks);
    src += blocks * 32;
    dst += blocks * 48;
    pairs -= blocks * 8;
  }
#endif
  convert_pairs_scalar(src, dst, pairs, t);
}

std::string size_text(int w, int h) {
  return std::to_string(w) + "x" + std::to_string(h);
}

}  // namespace

Status yuyv_to_bgr_into(std::span<const uint8_t> yuyv, int width_px, int height_px, int step_bytes,
                        uint8_t* dst, int dst_step_bytes) {
  if (width_px <= 0 || height_px <= 0 || width_px % 2 != 0) {
    return Error{"YUYV frame size " + size_text(width_px, height_px) +
                 " is invalid (width must be even and > 0)"};
  }
  if (step_bytes < 2 * width_px) {
    return Error{"YUYV row pitch " + std::to_string(step_bytes) + " is smaller than 2 x width " +
                 std::to_string(width_px)};
  }
  if (dst_step_bytes < 3 * width_px) {
    return Error{"BGR row pitch " + std::to_string(dst_step_bytes) + " is smaller than 3 x width " +
                 std::to_string(width_px)};
  }
  const size_t needed = static_cast<size_t>(step_bytes) * (height_px - 1) + 2 * width_px;
  if (yuyv.size() < needed) {
    return Error{"YUYV frame is truncated: " + std::to_string(yuyv.size()) + " bytes, " +
                 size_text(width_px, height_px) + " needs " + std::to_string(needed)};
  }
  const YuvTables& t = tables();
  for (int row = 0; row < height_px; ++row) {
    // Rows are written in order, so spilling into the next row is overwritten later; only the
    // last row must stay inside the buffer. The source is read 32 bytes per block, never past
    // the row's 2 * width bytes, since blocks cover whole pixel pairs.
    convert_row(yuyv.data() + static_cast<size_t>(row) * step_bytes,
                dst + static_cast<size_t>(row) * dst_step_bytes, width_px, row + 1 < height_px, t);
  }
  return {};
}

Status yuyv_to_bgr(std::span<const uint8_t> yuyv, int width_px, int height_px, int step_bytes,
                   cv::Mat& bgr) {
  if (width_px > 0 && height_px > 0) bgr.create(height_px, width_px, CV_8UC3);
  return yuyv_to_bgr_into(yuyv, width_px, height_px, step_bytes, bgr.data,
                          static_cast<int>(bgr.step));
}

}  // namespace stereoball::stereo
