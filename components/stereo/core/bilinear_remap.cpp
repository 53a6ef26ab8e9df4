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

// Pixels [from, to) of a row of n, one pixel per few vector instructions on the vector path;
// the border pixels and the row's last one (whose 4-byte store would reach past it) go through
// remap_pixel.
__attribute__((target("ssse3"))) void remap_span_ssse3(const cv::Mat& src, const short* xy,
                                                       const std::uint16_t* fraction,
                                                       std::uint8_t* out, int from, int to, int n) {
  const WeightRows& weights = weight_rows();
  const Source s(src);
  for (int x = from; x < to; ++x) {
    const int sx = xy[2 * x], sy = xy[2 * x + 1];
    const int f = fraction[x] & kFractionMask;
    if (s.fast(sx, sy) && x + 1 < n)
      blend_one(s, sx, sy, f, weights, out + 3 * x);
    else
      remap_pixel(src, sx, sy, f, out + 3 * x);
  }
}

// remap_row by remap_span_ssse3.
void remap_row_ssse3(const cv::Mat& src, const short* xy, const std::uint16_t* fraction,
                     std::uint8_t* out, int n) {
  remap_span_ssse3(src, xy, fraction, out, 0, n, n);
}

#undef SB_TOP_ORDER
#undef SB_BOTTOM_ORDER

// The same sum factored by axis: (32 - fy) * ((32 - fx) * a + fx * b) + fy * (...bottom...),
// exact in integers. The horizontal step fits 16 bits (<= 32 * 255), so one unsigned-by-signed
// byte multiply-add does it and one 16-bit multiply-add the vertical step: one pixel per
// 128-bit lane, eight pixels per block whose offsets and weights are worked out side by side.
constexpr int kBlock = 8;

// A block's per-pixel inputs, one 32-bit lane per pixel: its source offset, its horizontal
// weights (bytes 32 - fx, fx, twice) and its vertical ones (16-bit 32 - fy, fy).
struct BlockInputs {
  alignas(32) std::array<std::int32_t, kBlock> offset;
  __m256i across, down;
};

// Whether all eight pixels from xy lie on the vector path; if so their inputs.
__attribute__((target("avx2"))) inline bool block_inputs(const short* xy,
                                                         const std::uint16_t* fraction,
                                                         __m256i bounds, __m256i scale,
                                                         BlockInputs& in) {
  const __m256i pos = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(xy));
  const __m256i inside = _mm256_and_si256(_mm256_cmpgt_epi16(bounds, pos),
                                          _mm256_cmpgt_epi16(pos, _mm256_set1_epi16(-1)));
  if (_mm256_movemask_epi8(inside) != -1) return false;
  _mm256_store_si256(reinterpret_cast<__m256i*>(in.offset.data()), _mm256_madd_epi16(pos, scale));
  const __m128i f = _mm_loadu_si128(reinterpret_cast<const __m128i*>(fraction));
  const __m128i one = _mm_set1_epi16(kFractionOne), low = _mm_set1_epi16(kFractionOne - 1);
  const __m128i fx = _mm_and_si128(f, low);
  const __m128i fy = _mm_and_si128(_mm_srli_epi16(f, kFractionBits), low);
  const __m256i across =
      _mm256_cvtepu16_epi32(_mm_or_si128(_mm_sub_epi16(one, fx), _mm_slli_epi16(fx, 8)));
  in.across = _mm256_or_si256(across, _mm256_slli_epi32(across, 16));
  in.down = _mm256_or_si256(_mm256_cvtepu16_epi32(_mm_sub_epi16(one, fy)),
                            _mm256_slli_epi32(_mm256_cvtepu16_epi32(fy), 16));
  return true;
}

// A pixel's rows as one lane: bytes 0-7 from the top row (B0 G0 R0 B1 G1 R1 ...), 8-15 from
// the bottom row.
__attribute__((target("avx2"))) inline __m128i lane_of(const std::uint8_t* p, std::ptrdiff_t step) {
  return _mm_castpd_si128(
      _mm_loadh_pd(_mm_castsi128_pd(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p))),
                   reinterpret_cast<const double*>(p + step)));
}

// Pixels 2 * pair and 2 * pair + 1 of a block (low and high lane): each channel's value in the
// low byte of its 32-bit lane, B, G, R, 0.
template <int pair>
__attribute__((target("avx2"))) inline __m256i blend_pair(const Source& s, const BlockInputs& in) {
  const auto at = [&s, &in](int k) { return s.data + in.offset[static_cast<std::size_t>(k)]; };
  const __m256i rows = _mm256_inserti128_si256(
      _mm256_castsi128_si256(lane_of(at(2 * pair), s.step)), lane_of(at(2 * pair + 1), s.step), 1);
  // Per lane: each channel's top left, top right, bottom left, bottom right byte.
  const __m256i bytes =
      _mm256_shuffle_epi8(rows, _mm256_broadcastsi128_si256(_mm_setr_epi8(
                                    0, 3, 8, 11, 1, 4, 9, 12, 2, 5, 10, 13, -1, -1, -1, -1)));
  const __m256i which = _mm256_setr_epi32(2 * pair, 2 * pair, 2 * pair, 2 * pair, 2 * pair + 1,
                                          2 * pair + 1, 2 * pair + 1, 2 * pair + 1);
  const __m256i across = _mm256_maddubs_epi16(bytes, _mm256_permutevar8x32_epi32(in.across, which));
  const __m256i sum = _mm256_madd_epi16(across, _mm256_permutevar8x32_epi32(in.down, which));
  return _mm256_srai_epi32(_mm256_add_epi32(sum, _mm256_set1_epi32(kRounding)), kWeightShift);
}

// Eight pixels' 24 bytes; writes 28 (the last four belong to the next two pixels, which the
// caller writes afterwards).
__attribute__((target("avx2"))) inline void blend_block(const Source& s, const BlockInputs& in,
                                                        std::uint8_t* out) {
  // Lanes of pixels 0 2 4 6 | 1 3 5 7 as bytes B G R 0, then in order, then 3 bytes each.
  const __m256i bytes =
      _mm256_packus_epi16(_mm256_packs_epi32(blend_pair<0>(s, in), blend_pair<1>(s, in)),
                          _mm256_packs_epi32(blend_pair<2>(s, in), blend_pair<3>(s, in)));
  const __m256i ordered =
      _mm256_permutevar8x32_epi32(bytes, _mm256_setr_epi32(0, 4, 1, 5, 2, 6, 3, 7));
  const __m256i packed =
      _mm256_shuffle_epi8(ordered, _mm256_broadcastsi128_si256(_mm_setr_epi8(
                                       0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, -1, -1, -1, -1)));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm256_castsi256_si128(packed));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 12), _mm256_extracti128_si256(packed, 1));
}

bool cpu_has_avx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}

// remap_row eight pixels at a time where all eight lie on the vector path and two more follow
// (the last store reaches into them); the rest as remap_span_ssse3 does. Sources whose offsets
// do not fit the 16-bit multiply (rows over 32767 bytes) go to it whole.
__attribute__((target("avx2"))) void remap_row_avx2(const cv::Mat& src, const short* xy,
                                                    const std::uint16_t* fraction,
                                                    std::uint8_t* out, int n) {
  const Source s(src);
  constexpr std::ptrdiff_t kMaxStep = 32767;
  if (s.step > kMaxStep || src.rows > kMaxStep) {
    remap_span_ssse3(src, xy, fraction, out, 0, n, n);
    return;
  }
  const __m256i bounds = _mm256_set1_epi32(static_cast<int>(
      (static_cast<unsigned>(s.fast_rows) << 16) | static_cast<std::uint16_t>(s.fast_cols)));
  const __m256i scale =
      _mm256_set1_epi32(static_cast<int>((static_cast<unsigned>(s.step) << 16) | 3u));
  BlockInputs in;
  int x = 0;
  for (; x + kBlock + 2 <= n; x += kBlock) {
    if (block_inputs(xy + 2 * x, fraction + x, bounds, scale, in))
      blend_block(s, in, out + 3 * x);
    else
      remap_span_ssse3(src, xy, fraction, out, x, x + kBlock, n);
  }
  remap_span_ssse3(src, xy, fraction, out, x, n, n);
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
