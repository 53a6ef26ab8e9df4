#include "stereo/core/bilinear_remap.hpp"

#include <opencv2/imgproc.hpp>

#include <array>
#include <cstdint>
#include <cstring>

// The vector path needs SSSE3 (a byte shuffle), picked at run time: the build targets baseline
// x86-64. Elsewhere, and with SB_NO_CPU_DISPATCH (CMake SB_CPU_DISPATCH=OFF), the plain path.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(SB_NO_CPU_DISPATCH)
#define SB_REMAP_SSSE3 1
#include <immintrin.h>
#else
#define SB_REMAP_SSSE3 0
#endif

namespace stereoball::stereo {
namespace {

// Fixed-point maps hold 5 bits of fraction per axis (cv::INTER_BITS): index fy * 32 + fx.
constexpr int kFractionBits = 5;
constexpr int kFractionOne = 1 << kFractionBits;
constexpr int kFractionMask = (1 << (2 * kFractionBits)) - 1;
// OpenCV's weights are (1 - fx/32)(1 - fy/32) ... scaled by 2^15: exactly 32 times the integer
// products below (the fractions are multiples of 1/32), so its (sum + 2^14) >> 15 equals
// (sum of the products below + 2^9) >> 10.
constexpr int kWeightShift = 2 * kFractionBits;
constexpr int kRounding = 1 << (kWeightShift - 1);

// The four neighbours' weights of a fraction index, summing to 1024.
struct Weights {
  int top_left, top_right, bottom_left, bottom_right;
};

Weights weights_of(int fraction) {
  const int fx = fraction & (kFractionOne - 1), fy = fraction >> kFractionBits;
  return {(kFractionOne - fx) * (kFractionOne - fy), fx * (kFractionOne - fy),
          (kFractionOne - fx) * fy, fx * fy};
}

// One BGR pixel from source pixel (sx, sy) and its right and lower neighbours, those outside
// src counting as 0 (BORDER_CONSTANT).
void remap_pixel(const cv::Mat& src, int sx, int sy, int fraction, std::uint8_t* out) {
  const Weights w = weights_of(fraction);
  int sum[3] = {kRounding, kRounding, kRounding};
  const auto add = [&](int x, int y, int weight) {
    if (x < 0 || y < 0 || x >= src.cols || y >= src.rows) return;
    const std::uint8_t* p = src.ptr<std::uint8_t>(y) + 3 * x;
    for (int c = 0; c < 3; ++c) sum[c] += weight * p[c];
  };
  add(sx, sy, w.top_left);
  add(sx + 1, sy, w.top_right);
  add(sx, sy + 1, w.bottom_left);
  add(sx + 1, sy + 1, w.bottom_right);
  for (int c = 0; c < 3; ++c) out[c] = static_cast<std::uint8_t>(sum[c] >> kWeightShift);
}

void remap_row(const cv::Mat& src, const short* xy, const std::uint16_t* fraction,
               std::uint8_t* out, int n) {
  for (int x = 0; x < n; ++x)
    remap_pixel(src, xy[2 * x], xy[2 * x + 1], fraction[x] & kFractionMask, out + 3 * x);
}

#if SB_REMAP_SSSE3

bool cpu_has_ssse3() {
  static const bool has = __builtin_cpu_supports("ssse3");
  return has;
}

// Per fraction index, the weights of a source row's left and right pixel as the two 16-bit
// halves of a word: the multiply-add instruction's operand.
struct WeightPairs {
  std::array<std::uint32_t, kFractionMask + 1> top, bottom;
};

const WeightPairs& weight_pairs() {
  static const WeightPairs pairs = [] {
    WeightPairs p{};
    for (int f = 0; f <= kFractionMask; ++f) {
      const Weights w = weights_of(f);
      p.top[f] = static_cast<std::uint32_t>(w.top_left) | static_cast<std::uint32_t>(w.top_right)
                                                              << 16;
      p.bottom[f] = static_cast<std::uint32_t>(w.bottom_left) |
                    static_cast<std::uint32_t>(w.bottom_right) << 16;
    }
    return p;
  }();
  return pairs;
}

// remap_row with one pixel per few vector instructions where its 2x2 neighbourhood lies inside
// src with two bytes to spare (two 8-byte loads, one per source row); the border pixels and the
// row's last one (whose 4-byte store would reach past it) go through remap_pixel.
__attribute__((target("ssse3"))) void remap_row_ssse3(const cv::Mat& src, const short* xy,
                                                      const std::uint16_t* fraction,
                                                      std::uint8_t* out, int n) {
  const WeightPairs& pairs = weight_pairs();
  const auto step = static_cast<std::ptrdiff_t>(src.step);
  // Bytes 0-7: the top row's B0 G0 R0 B1 G1 R1 (and two more), 8-15 the bottom row's; as 16-bit
  // lanes B0 B1 G0 G1 R0 R1 0 0, so that one multiply-add gives each channel's row sum.
  const __m128i top_order = _mm_setr_epi8(0, -1, 3, -1, 1, -1, 4, -1, 2, -1, 5, -1, -1, -1, -1, -1);
  const __m128i bottom_order =
      _mm_setr_epi8(8, -1, 11, -1, 9, -1, 12, -1, 10, -1, 13, -1, -1, -1, -1, -1);
  const __m128i rounding = _mm_set1_epi32(kRounding);
  // sx <= cols - 3: the 8 bytes from pixel sx stay in its row.
  const int fast_cols = src.cols - 2, fast_rows = src.rows - 1;
  for (int x = 0; x < n; ++x) {
    const int sx = xy[2 * x], sy = xy[2 * x + 1];
    const int f = fraction[x] & kFractionMask;
    if (sx < 0 || sy < 0 || sx >= fast_cols || sy >= fast_rows || x + 1 == n) {
      remap_pixel(src, sx, sy, f, out + 3 * x);
      continue;
    }
    const std::uint8_t* p = src.data + sy * step + 3 * sx;
    const __m128i both =
        _mm_unpacklo_epi64(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)),
                           _mm_loadl_epi64(reinterpret_cast<const __m128i*>(p + step)));
    const __m128i top = _mm_madd_epi16(_mm_shuffle_epi8(both, top_order),
                                       _mm_set1_epi32(static_cast<int>(pairs.top[f])));
    const __m128i bottom = _mm_madd_epi16(_mm_shuffle_epi8(both, bottom_order),
                                          _mm_set1_epi32(static_cast<int>(pairs.bottom[f])));
    const __m128i sum =
        _mm_srai_epi32(_mm_add_epi32(_mm_add_epi32(top, bottom), rounding), kWeightShift);
    const __m128i bytes = _mm_packus_epi16(_mm_packs_epi32(sum, sum), sum);
    // Four bytes: the fourth is the next pixel's first, written next.
    const int bgr = _mm_cvtsi128_si32(bytes);
    std::memcpy(out + 3 * x, &bgr, 4);
  }
}

#endif

}  // namespace

void remap_bilinear(const cv::Mat& src, cv::Mat& dst, const cv::Mat& xy, const cv::Mat& frac) {
  const bool shares = dst.datastart != nullptr && dst.datastart == src.datastart;
  if (src.type() != CV_8UC3 || src.empty() || xy.type() != CV_16SC2 || frac.type() != CV_16UC1 ||
      xy.size() != frac.size() || shares) {
    cv::remap(src, dst, xy, frac, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
    return;
  }
  dst.create(xy.size(), src.type());
  for (int y = 0; y < xy.rows; ++y) {
    const short* map = xy.ptr<short>(y);
    const auto* fraction = frac.ptr<std::uint16_t>(y);
    auto* out = dst.ptr<std::uint8_t>(y);
#if SB_REMAP_SSSE3
    if (cpu_has_ssse3()) {
      remap_row_ssse3(src, map, fraction, out, xy.cols);
      continue;
    }
#endif
    remap_row(src, map, fraction, out, xy.cols);
  }
}

}  // namespace stereoball::stereo
