#include "stereo/core/bilinear_remap.hpp"

#include <opencv2/imgproc.hpp>

#include <array>
#include <cstdint>
#include <cstring>

// The vector paths need SSSE3 (a byte shuffle) or AVX2, picked at run time: the build targets
// baseline x86-64. Elsewhere, and with SB_NO_CPU_DISPATCH (CMake
// SB_CPU_DISPATCH=OFF), the plain path.
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

// Per fraction index, the weights of a source row's left and right pixel in the 16-bit lanes
// the multiply-add meets them in (left, right for each of B, G, R, then 0, 0): loaded whole, no
// shuffle spent on spreading them (the shuffle unit is what the pixel loop waits on).
struct WeightRows {
  alignas(16) std::array<std::array<std::int16_t, 8>, kFractionMask + 1> top, bottom;
};

const WeightRows& weight_rows() {
  static const WeightRows rows = [] {
    WeightRows r{};
    for (int f = 0; f <= kFractionMask; ++f) {
      const Weights w = weights_of(f);
      const auto left_right = [](int left, int right) {
        const auto l = static_cast<std::int16_t>(left), r = static_cast<std::int16_t>(right);
        return std::array<std::int16_t, 8>{l, r, l, r, l, r, 0, 0};
      };
      r.top[static_cast<std::size_t>(f)] = left_right(w.top_left, w.top_right);
      r.bottom[static_cast<std::size_t>(f)] = left_right(w.bottom_left, w.bottom_right);
    }
    return r;
  }();
  return rows;
}

// The source image as the vector paths read it: pixel (x, y) at data + y * step + 3 * x.
// Pixels whose 2x2 neighbourhood lies inside with two bytes to spare (sx <= cols - 3: the
// 8-byte load from pixel sx stays in its row) take a vector path.
struct Source {
  const std::uint8_t* data;
  std::ptrdiff_t step;
  int fast_cols, fast_rows;

  explicit Source(const cv::Mat& src)
      : data(src.data),
        step(static_cast<std::ptrdiff_t>(src.step)),
        fast_cols(src.cols - 2),
        fast_rows(src.rows - 1) {}
  bool fast(int sx, int sy) const { return sx >= 0 && sy >= 0 && sx < fast_cols && sy < fast_rows; }
  const std::uint8_t* at(int sx, int sy) const { return data + sy * step + 3 * sx; }
};

// Bytes 0-7: a pixel's top row B0 G0 R0 B1 G1 R1 (and two more), 8-15 its bottom row; as 16-bit
// lanes B0 B1 G0 G1 R0 R1 0 0, so that one multiply-add gives each channel's row sum.
#define SB_TOP_ORDER 0, -1, 3, -1, 1, -1, 4, -1, 2, -1, 5, -1, -1, -1, -1, -1
#define SB_BOTTOM_ORDER 8, -1, 11, -1, 9, -1, 12, -1, 10, -1, 13, -1, -1, -1, -1, -1

// A pixel's top and bottom source row bytes (blend_one's layout).
__attribute__((target("ssse3"))) inline __m128i rows_of(const Source& s, int sx, int sy) {
  const std::uint8_t* p = s.at(sx, sy);
  return _mm_unpacklo_epi64(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)),
                            _mm_loadl_epi64(reinterpret_cast<const __m128i*>(p + s.step)));
}

// One pixel on the vector path: its two source rows' bytes, weighted and rounded; writes four
// bytes (the fourth is the next pixel's first: the caller writes that one afterwards).
__attribute__((target("ssse3"))) inline void blend_one(const Source& s, int sx, int sy, int f,
                                                       const WeightRows& weights,
                                                       std::uint8_t* out) {
  const auto index = static_cast<std::size_t>(f);
  const __m128i both = rows_of(s, sx, sy);
  const __m128i top =
      _mm_madd_epi16(_mm_shuffle_epi8(both, _mm_setr_epi8(SB_TOP_ORDER)),
                     _mm_load_si128(reinterpret_cast<const __m128i*>(weights.top[index].data())));
  const __m128i bottom = _mm_madd_epi16(
      _mm_shuffle_epi8(both, _mm_setr_epi8(SB_BOTTOM_ORDER)),
      _mm_load_si128(reinterpret_cast<const __m128i*>(weights.bottom[index].data())));
  const __m128i sum = _mm_srai_epi32(
      _mm_add_epi32(_mm_add_epi32(top, bottom), _mm_set1_epi32(kRounding)), kWeightShift);
  // Each channel's value (<= 255) is the low byte of its 32-bit lane.
  const int bgr = _mm_cvtsi128_si32(_mm_shuffle_epi8(
      sum, _mm_setr_epi8(0, 4, 8, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1)));
  std::memcpy(out, &bgr, 4);
}

// remap_row with one pixel per few vector instructions on the vector path; the border pixels
// and the row's last one (whose 4-byte store would reach past it) go through remap_pixel.
__attribute__((target("ssse3"))) void remap_row_ssse3(const cv::Mat& src, const short* xy,
                                                      const std::uint16_t* fraction,
                                                      std::uint8_t* out, int n) {
  const WeightRows& weights = weight_rows();
  const Source s(src);
  for (int x = 0; x < n; ++x) {
    const int sx = xy[2 * x], sy = xy[2 * x + 1];
    const int f = fraction[x] & kFractionMask;
    if (s.fast(sx, sy) && x + 1 < n)
      blend_one(s, sx, sy, f, weights, out + 3 * x);
    else
      remap_pixel(src, sx, sy, f, out + 3 * x);
  }
}

#undef SB_TOP_ORDER
#undef SB_BOTTOM_ORDER

bool cpu_has_avx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}

// The same sum factored by axis: (32 - fy) * ((32 - fx) * a + fx * b) + fy * (...bottom...),
// exact in integers. The horizontal step fits 16 bits (<= 32 * 255), so one unsigned-by-signed
// byte multiply-add does it, and one 16-bit multiply-add the vertical step: two multiplies for
// a pixel's 12 source bytes, one pixel per 128-bit lane.
struct AxisWeights {
  // Per fx: bytes 32 - fx, fx repeated (the horizontal pairs).
  alignas(16) std::array<std::array<std::int8_t, 16>, kFractionOne> across;
  // Per fy: 16-bit 32 - fy, fy repeated (the vertical pairs).
  alignas(16) std::array<std::array<std::int16_t, 8>, kFractionOne> down;
};

const AxisWeights& axis_weights() {
  static const AxisWeights weights = [] {
    AxisWeights w{};
    for (std::size_t f = 0; f < kFractionOne; ++f)
      for (std::size_t i = 0; i < 16; i += 2) {
        const auto near = static_cast<std::int8_t>(kFractionOne - static_cast<int>(f));
        const auto far = static_cast<std::int8_t>(f);
        w.across[f][i] = near;
        w.across[f][i + 1] = far;
        w.down[f][i / 2] = static_cast<std::int16_t>(i % 4 == 0 ? near : far);
      }
    return w;
  }();
  return weights;
}

// A pixel's rows as one lane: bytes 0-7 from the top row (B0 G0 R0 B1 G1 R1 ...), 8-15 from
// the bottom row.
__attribute__((target("avx2"))) inline __m128i lane_of(const Source& s, int sx, int sy) {
  const std::uint8_t* p = s.at(sx, sy);
  return _mm_castpd_si128(
      _mm_loadh_pd(_mm_castsi128_pd(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p))),
                   reinterpret_cast<const double*>(p + s.step)));
}

// a in the low lane, b in the high one.
__attribute__((target("avx2"))) inline __m256i lanes(__m128i a, __m128i b) {
  return _mm256_inserti128_si256(_mm256_castsi128_si256(a), b, 1);
}

// Two rows of a weight table (by axis fraction) as the low and high lane.
template <typename Table>
__attribute__((target("avx2"))) inline __m256i lanes(const Table& table, int a, int b) {
  const auto row = [&table](int f) {
    return reinterpret_cast<const __m128i*>(table[static_cast<std::size_t>(f)].data());
  };
  return lanes(_mm_load_si128(row(a)), _mm_load_si128(row(b)));
}

// Two pixels (a, then b) from their rows and fraction indices; writes eight bytes: the six of
// the two pixels and two of the next pixel's (the caller writes that one afterwards).
__attribute__((target("avx2"))) inline void blend_two(__m128i rows_a, __m128i rows_b, int fa,
                                                      int fb, const AxisWeights& w,
                                                      std::uint8_t* out) {
  // Per lane: each channel's top left, top right, bottom left, bottom right byte.
  const __m256i order = _mm256_broadcastsi128_si256(
      _mm_setr_epi8(0, 3, 8, 11, 1, 4, 9, 12, 2, 5, 10, 13, -1, -1, -1, -1));
  const __m256i bytes = _mm256_shuffle_epi8(lanes(rows_a, rows_b), order);
  const __m256i rows = _mm256_maddubs_epi16(
      bytes, lanes(w.across, fa & (kFractionOne - 1), fb & (kFractionOne - 1)));
  const __m256i sum =
      _mm256_madd_epi16(rows, lanes(w.down, fa >> kFractionBits, fb >> kFractionBits));
  const __m256i value =
      _mm256_srai_epi32(_mm256_add_epi32(sum, _mm256_set1_epi32(kRounding)), kWeightShift);
  // Each channel's value is the low byte of its 32-bit lane: a's to bytes 0-2, b's to 3-5.
  const __m256i packed = _mm256_shuffle_epi8(
      value, _mm256_setr_epi8(0, 4, 8, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1,  //
                              -1, -1, -1, 0, 4, 8, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1));
  _mm_storel_epi64(
      reinterpret_cast<__m128i*>(out),
      _mm_or_si128(_mm256_castsi256_si128(packed), _mm256_extracti128_si256(packed, 1)));
}

// remap_row two pixels at a time where both lie on the vector path and a third follows (the
// eight-byte store reaches into it); the rest one at a time as remap_row_ssse3 does.
__attribute__((target("avx2"))) void remap_row_avx2(const cv::Mat& src, const short* xy,
                                                    const std::uint16_t* fraction,
                                                    std::uint8_t* out, int n) {
  const WeightRows& weights = weight_rows();
  const AxisWeights& axis = axis_weights();
  const Source s(src);
  int x = 0;
  while (x < n) {
    const int sx = xy[2 * x], sy = xy[2 * x + 1];
    const int f = fraction[x] & kFractionMask;
    const bool fast = s.fast(sx, sy);
    if (fast && x + 2 < n && s.fast(xy[2 * x + 2], xy[2 * x + 3])) {
      blend_two(lane_of(s, sx, sy), lane_of(s, xy[2 * x + 2], xy[2 * x + 3]), f,
                fraction[x + 1] & kFractionMask, axis, out + 3 * x);
      x += 2;
      continue;
    }
    if (fast && x + 1 < n)
      blend_one(s, sx, sy, f, weights, out + 3 * x);
    else
      remap_pixel(src, sx, sy, f, out + 3 * x);
    ++x;
  }
}

#endif

}  // namespace

void remap_bilinear(const cv::Mat& src, cv::Mat& dst, const cv::Mat& xy, const cv::Mat& frac) {
  remap_bilinear(src, dst, xy, frac, RemapPath::kAvx2);
}

void remap_bilinear(const cv::Mat& src, cv::Mat& dst, const cv::Mat& xy, const cv::Mat& frac,
                    RemapPath fastest) {
  const bool shares = dst.datastart != nullptr && dst.datastart == src.datastart;
  if (src.type() != CV_8UC3 || src.empty() || xy.type() != CV_16SC2 || frac.type() != CV_16UC1 ||
      xy.size() != frac.size() || shares) {
    cv::remap(src, dst, xy, frac, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
    return;
  }
  dst.create(xy.size(), src.type());
#if SB_REMAP_SSSE3
  const bool vector_path = fastest >= RemapPath::kSsse3 && cpu_has_ssse3();
#else
  const bool vector_path = false;
#endif
  // Without the vector path OpenCV's own remap is the faster way to the same bits (the plain
  // loop is the reference, and the border pixels' path).
  if (!vector_path && fastest != RemapPath::kPlain) {
    cv::remap(src, dst, xy, frac, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
    return;
  }
  auto row = remap_row;
#if SB_REMAP_SSSE3
  if (vector_path) row = remap_row_ssse3;
  if (vector_path && fastest >= RemapPath::kAvx2 && cpu_has_avx2()) row = remap_row_avx2;
#endif
  for (int y = 0; y < xy.rows; ++y)
    row(src, xy.ptr<short>(y), frac.ptr<std::uint16_t>(y), dst.ptr<std::uint8_t>(y), xy.cols);
}

}  // namespace stereoball::stereo
