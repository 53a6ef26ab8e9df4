#include "ball_detector/core/edge_map.hpp"

#include "ball_detector/core/cpu_dispatch.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#if SB_HAVE_AVX2_KERNELS
#include <immintrin.h>
#endif

namespace stereoball::ball_detector {
namespace {

constexpr int kMaxL1Gradient = 2048;  // 3x3 Sobel: |dx| + |dy| <= 2 * 4 * 255
// canny_thresholds reads every kThresholdSampleStep-th row and column of the gradient, from 0.
constexpr int kThresholdSampleStep = 2;

// Yokoi connectivity number (8-connectivity) of the neighbour code; 1 = simple point.
int connectivity8(int code) {
  auto bg = [code](int i) { return ((code >> (i & 7)) & 1) ? 0 : 1; };
  int n = 0;
  for (int k = 0; k < 8; k += 2) n += bg(k) - bg(k) * bg(k + 1) * bg(k + 2);
  return n;
}

std::array<bool, 256> build_staircase_table() {
  std::array<bool, 256> table{};
  for (int code = 0; code < 256; ++code) {
    auto on = [code](int i) { return ((code >> i) & 1) != 0; };
    // 4-neighbours are the even bits: E=0, S=2, W=4, N=6.
    const bool corner =
        (on(0) && on(2)) || (on(2) && on(4)) || (on(4) && on(6)) || (on(6) && on(0));
    table[code] = corner && connectivity8(code) == 1;
  }
  return table;
}

// Code from three row pointers; bit order E, SE, S, SW, W, NW, N, NE.
inline int code_at(const uchar* up, const uchar* mid, const uchar* down, int x) {
  return (mid[x + 1] ? 1 : 0) | (down[x + 1] ? 2 : 0) | (down[x] ? 4 : 0) | (down[x - 1] ? 8 : 0) |
         (mid[x - 1] ? 16 : 0) | (up[x - 1] ? 32 : 0) | (up[x] ? 64 : 0) | (up[x + 1] ? 128 : 0);
}

// canny_thresholds measures a row in stretches of this many columns (a multiple of the sample
// step, so every stretch starts on a sampled column).
constexpr int kL1Chunk = 1024;
static_assert(kL1Chunk % kThresholdSampleStep == 0);

// min(|gx| + |gy|, kMaxL1Gradient) of n pixels, in 16-bit lanes: capping each term first keeps
// the sum below 2^16 (and -32768 has no 16-bit opposite, but its magnitude is capped anyway).
SB_AVX2_CLONE void capped_l1_row(const short* __restrict gx, const short* __restrict gy, int n,
                                 std::uint16_t* __restrict out) {
  constexpr std::uint16_t kCap = kMaxL1Gradient;
  for (int x = 0; x < n; ++x) {
    const auto ax = static_cast<std::uint16_t>(gx[x] < 0 ? -gx[x] : gx[x]);
    const auto ay = static_cast<std::uint16_t>(gy[x] < 0 ? -gy[x] : gy[x]);
    const auto sum = static_cast<std::uint16_t>(std::min(ax, kCap) + std::min(ay, kCap));
    out[x] = std::min(sum, kCap);
  }
}

// One BGR row with its brightness removed (remove_brightness). Three times a channel minus the
// sum is three times its difference from the mean: integers throughout, one division.
SB_AVX2_CLONE void brightness_free_row(const std::uint8_t* __restrict bgr,
                                       std::uint8_t* __restrict out, int n) {
  for (int i = 0; i < 3 * n; i += 3) {
    const int sum = bgr[i] + bgr[i + 1] + bgr[i + 2];
    for (int c = 0; c < 3; ++c) {
      const int v = 128 + kBrightnessFreeGain * (3 * bgr[i + c] - sum) / 3;
      out[i + c] = static_cast<std::uint8_t>(std::clamp(v, 0, 255));
    }
  }
}

}  // namespace

Status EdgeParams::validate() const {
  if (!(noise_factor > 0.0 && noise_factor <= 100.0))
    return Error{"noise_factor must be in (0, 100]"};
  if (!(high_percentile > 0.0 && high_percentile < 1.0))
    return Error{"high_percentile must be in (0, 1)"};
  if (!(contrast_fraction >= 0.0 && contrast_fraction <= 1.0))
    return Error{"contrast_fraction must be in [0, 1]"};
  if (!(denoise_median >= 0.0)) return Error{"denoise_median must be >= 0"};
  if (!(low_ratio > 0.0 && low_ratio <= 1.0)) return Error{"low_ratio must be in (0, 1]"};
  if (!(min_high_threshold >= 1.0 && min_high_threshold <= 2040.0))
    return Error{"min_high_threshold must be in [1, 2040]"};
  if (!(max_high_threshold >= min_high_threshold))
    return Error{"max_high_threshold must be >= min_high_threshold"};
  return {};
}

void BitImage::reset(int width, int height) {
  width_ = width;
  height_ = height;
  stride_ = (width_ + 63) / 64 + 1;
  words_.assign(static_cast<size_t>(stride_) * height_, 0);
}

namespace {

// Packs n bytes of a row (non-zero = set) into words that start clear, bit x % 64 of word x / 64.
void pack_row(const uchar* src, int n, std::uint64_t* dst) {
  int x = 0;
  for (; x + 8 <= n; x += 8) {
    std::uint64_t v;
    std::memcpy(&v, src + x, 8);
    if (v == 0) continue;
    // Normalise bytes to 0/1, then gather the 8 low bits into one byte.
    v = ((v | (v >> 1) | (v >> 2) | (v >> 3) | (v >> 4) | (v >> 5) | (v >> 6) | (v >> 7)) &
         0x0101010101010101ull);
    const std::uint64_t packed = (v * 0x0102040810204080ull) >> 56;
    dst[x >> 6] |= packed << (x & 63);
  }
  for (; x < n; ++x)
    if (src[x]) dst[x >> 6] |= std::uint64_t{1} << (x & 63);
}

#if SB_HAVE_AVX2_KERNELS
// pack_row a word (64 bytes, two compares and two byte masks) at a time; the plain loop packs
// the rest, which starts a word of its own.
SB_TARGET_AVX2 void pack_row_avx2(const uchar* src, int n, std::uint64_t* dst) {
  const __m256i zero = _mm256_setzero_si256();
  int x = 0;
  for (; x + 64 <= n; x += 64) {
    const __m256i a = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(src + x));
    const __m256i b = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(src + x + 32));
    const auto clear_a =
        static_cast<std::uint32_t>(_mm256_movemask_epi8(_mm256_cmpeq_epi8(a, zero)));
    const auto clear_b =
        static_cast<std::uint32_t>(_mm256_movemask_epi8(_mm256_cmpeq_epi8(b, zero)));
    dst[x >> 6] = ~(std::uint64_t{clear_b} << 32 | clear_a);
  }
  pack_row(src + x, n - x, dst + (x >> 6));
}
#endif

}  // namespace

void BitImage::assign(const cv::Mat& binary) {
  CV_Assert(binary.type() == CV_8UC1);
  reset(binary.cols, binary.rows);
  for (int y = 0; y < height_; ++y) {
    const uchar* src = binary.ptr<uchar>(y);
    std::uint64_t* dst = words_.data() + static_cast<size_t>(y) * stride_;
#if SB_HAVE_AVX2_KERNELS
    if (cpu_has_avx2()) {
      pack_row_avx2(src, width_, dst);
      continue;
    }
#endif
    pack_row(src, width_, dst);
  }
}

cv::Mat to_grey(const cv::Mat& image) {
  if (image.type() == CV_8UC1) return image;
  cv::Mat grey;
  if (image.type() == CV_8UC3)
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  else if (image.type() == CV_8UC4)
    cv::cvtColor(image, grey, cv::COLOR_BGRA2GRAY);
  return grey;
}

namespace {

// The histogram canny_thresholds takes its quantiles from: min(|dx| + |dy|, kMaxL1Gradient) of
// every kThresholdSampleStep-th column of the rows added.
class SampledGradients {
 public:
  /// Counts the sampled columns of one row of cols derivatives.
  void add_row(const short* gx, const short* gy, int cols) {
    // The magnitudes of a stretch of row first (vector code, every column), then the samples.
    std::array<std::uint16_t, kL1Chunk> l1;
    for (int x0 = 0; x0 < cols; x0 += kL1Chunk) {
      const int n = std::min(kL1Chunk, cols - x0);
      capped_l1_row(gx + x0, gy + x0, n, l1.data());
      for (int x = 0; x < n; x += kThresholdSampleStep) ++hist_[l1[static_cast<std::size_t>(x)]];
    }
    samples_ += (cols + kThresholdSampleStep - 1) / kThresholdSampleStep;
  }
  /// Smallest magnitude m with more than floor(q * samples) samples at or below it.
  int quantile(double q) const {
    const int target = static_cast<int>(q * samples_);
    int cumulative = 0;
    for (int m = 0; m <= kMaxL1Gradient; ++m) {
      cumulative += hist_[static_cast<std::size_t>(m)];
      if (cumulative > target) return m;
    }
    return kMaxL1Gradient;
  }
  /// Whether the median of all samples (total of them, of which these are some) already
  /// certainly exceeds level: too many of them lie above it for the rest to pull it down.
  bool median_above(double level, int total) const {
    if (!(level >= 0.0 && level < kMaxL1Gradient)) return false;
    const int floor_level = static_cast<int>(level);  // an integer median > level iff > this
    int at_most = 0;
    for (int m = 0; m <= floor_level; ++m) at_most += hist_[static_cast<std::size_t>(m)];
    // quantile(0.5) > floor_level iff the samples at most floor_level, of all, are <= target.
    const int target = static_cast<int>(0.5 * total);
    return samples_ - at_most >= total - target;
  }
  /// The thresholds of the samples counted.
  CannyThresholds thresholds(const EdgeParams& params) const {
    CannyThresholds t;
    t.median_gradient = quantile(0.5);
    // Noise term: flat regions dominate the median. Contrast term: strong edges set the scale
    // when they are plentiful, so a textured, well-lit scene is not flooded with weak edges.
    const double high = std::max(params.noise_factor * t.median_gradient,
                                 params.contrast_fraction * quantile(params.high_percentile));
    t.high = std::clamp(high, params.min_high_threshold, params.max_high_threshold);
    t.low = t.high * params.low_ratio;
    return t;
  }

 private:
  std::array<int, kMaxL1Gradient + 1> hist_{};
  int samples_ = 0;
};

// How many samples canny_thresholds takes of a rows x cols gradient.
int sample_count(int rows, int cols) {
  return ((rows + kThresholdSampleStep - 1) / kThresholdSampleStep) *
         ((cols + kThresholdSampleStep - 1) / kThresholdSampleStep);
}

}  // namespace

CannyThresholds canny_thresholds(const cv::Mat& dx, const cv::Mat& dy, const EdgeParams& params) {
  // Every second row and column: the quantiles barely move, the cost drops fourfold.
  SampledGradients samples;
  for (int y = 0; y < dx.rows; y += kThresholdSampleStep)
    samples.add_row(dx.ptr<short>(y), dy.ptr<short>(y), dx.cols);
  return samples.thresholds(params);
}

const std::array<bool, 256>& staircase_table() {
  static const std::array<bool, 256> table = build_staircase_table();
  return table;
}

int neighbour_code(const cv::Mat& binary, int x, int y) {
  return code_at(binary.ptr<uchar>(y - 1), binary.ptr<uchar>(y), binary.ptr<uchar>(y + 1), x);
}

namespace {

// The outer frame has no full neighbourhood; clearing it keeps the pass branch-free.
void clear_frame(cv::Mat& binary) {
  binary.row(0).setTo(0);
  binary.row(binary.rows - 1).setTo(0);
  binary.col(0).setTo(0);
  binary.col(binary.cols - 1).setTo(0);
}

}  // namespace

std::uint64_t staircase_bits(std::uint64_t e, std::uint64_t se, std::uint64_t s, std::uint64_t sw,
                             std::uint64_t w, std::uint64_t nw, std::uint64_t n, std::uint64_t ne) {
  const std::uint64_t corner = (e & s) | (s & w) | (w & n) | (n & e);
  // connectivity8, one term per 4-neighbour: background, and foreground among the next two
  // clockwise. Simple point: exactly one term set.
  const std::uint64_t t0 = ~e & (se | s), t2 = ~s & (sw | w), t4 = ~w & (nw | n),
                      t6 = ~n & (ne | e);
  const std::uint64_t two_or_more = (t0 & t2) | (t4 & t6) | ((t0 | t2) & (t4 | t6));
  return corner & (t0 | t2 | t4 | t6) & ~two_or_more;
}

namespace {

// A word of a packed row and its pixels' west and east neighbours as words (bit i of west is
// pixel i - 1, the word before's last pixel for i = 0; east likewise pixel i + 1).
struct WordPlanes {
  std::uint64_t west = 0, centre = 0, east = 0;
  WordPlanes(const std::uint64_t* row, int word) : centre(row[word]) {
    west = centre << 1 | (word > 0 ? row[word - 1] >> 63 : 0);
    east = centre >> 1 | row[word + 1] << 63;  // rows are padded by a word
  }
};

}  // namespace

int thin_staircase(cv::Mat& binary, BitImage& bits) {
  CV_Assert(binary.type() == CV_8UC1 && bits.width() == binary.cols &&
            bits.height() == binary.rows);
  if (binary.rows < 3 || binary.cols < 3) return 0;
  clear_frame(binary);
  const int w = binary.cols, h = binary.rows;
  for (int x = 0; x < w; ++x) {  // the same frame in the packed copy
    bits.clear(x, 0);
    bits.clear(x, h - 1);
  }
  for (int y = 1; y < h - 1; ++y) {
    bits.clear(0, y);
    bits.clear(w - 1, y);
  }
  int removed = 0;
  for (int y = 1; y < h - 1; ++y) {
    std::uint64_t* mid = bits.mutable_row(y);
    uchar* pixels = binary.ptr<uchar>(y);
    for (int wi = 0; wi * 64 < w; ++wi) {
      if (mid[wi] == 0) continue;
      // Raster order with removals at once, as in the byte pass: the row above and the word
      // before are done, the row below and the east neighbours not yet visited. Of the pixels
      // still to visit, the first the table removes is removed; that changes only the west
      // neighbour of the pixel after it, so the test is redone for the pixels after it.
      const WordPlanes up(bits.row(y - 1), wi), down(bits.row(y + 1), wi), here(mid, wi);
      const std::uint64_t before = wi > 0 ? mid[wi - 1] >> 63 : 0;
      std::uint64_t word = here.centre, todo = word;
      for (;;) {
        const std::uint64_t removable =
            todo & staircase_bits(here.east, down.east, down.centre, down.west, word << 1 | before,
                                  up.west, up.centre, up.east);
        if (removable == 0) break;
        const std::uint64_t first = removable & (~removable + 1);
        word &= ~first;
        todo &= ~((first << 1) - 1);  // the pixels after it (none after bit 63)
        pixels[wi * 64 + std::countr_zero(first)] = 0;
        ++removed;
      }
      mid[wi] = word;
    }
  }
  return removed;
}

int thin_staircase(cv::Mat& binary) {
  CV_Assert(binary.type() == CV_8UC1);
  if (binary.rows < 3 || binary.cols < 3) return 0;
  clear_frame(binary);
  const auto& table = staircase_table();
  int removed = 0;
  for (int y = 1; y < binary.rows - 1; ++y) {
    const uchar* up = binary.ptr<uchar>(y - 1);
    uchar* mid = binary.ptr<uchar>(y);
    const uchar* down = binary.ptr<uchar>(y + 1);
    for (int x = 1; x < binary.cols - 1; ++x) {
      // Edge maps are sparse: skip eight empty pixels at a time.
      if (x + 8 <= binary.cols) {
        std::uint64_t eight;
        std::memcpy(&eight, mid + x, 8);
        if (eight == 0) {
          x += 7;
          continue;
        }
      }
      if (!mid[x]) continue;
      // In place: a removed pixel is already gone when its neighbours are examined, so an
      // L never loses both of its pixels.
      if (table[code_at(up, mid, down, x)]) {
        mid[x] = 0;
        ++removed;
      }
    }
  }
  return removed;
}

namespace {

void grey_sobel(const cv::Mat& grey, cv::Mat& dx, cv::Mat& dy) {
  // A crop's Sobel reads the parent image's pixels around it (its border is not replicated),
  // which cv::spatialGradient does not; on a whole image both are equal, and spatialGradient
  // makes dx and dy in one pass, about a quarter faster.
  if (!grey.isSubmatrix()) {
    cv::spatialGradient(grey, dx, dy, 3, cv::BORDER_REPLICATE);
    return;
  }
  cv::Sobel(grey, dx, CV_16S, 1, 0, 3, 1.0, 0.0, cv::BORDER_REPLICATE);
  cv::Sobel(grey, dy, CV_16S, 0, 1, 3, 1.0, 0.0, cv::BORDER_REPLICATE);
}

// 3x3 Sobel at column x of three rows (above, this, below), each readable at x - 1 and x + 1.
// The results fit in 16 bits (|gx|, |gy| <= 1020, l1 <= 2040): kept at that width, the
// vectorised loops below work on twice as many pixels per instruction as in int.
[[gnu::always_inline]] inline void sobel_at(const std::uint8_t* __restrict up,
                                            const std::uint8_t* __restrict mid,
                                            const std::uint8_t* __restrict down, int x,
                                            std::int16_t& gx, std::int16_t& gy, std::int16_t& l1) {
  gx = static_cast<std::int16_t>((up[x + 1] - up[x - 1]) + 2 * (mid[x + 1] - mid[x - 1]) +
                                 (down[x + 1] - down[x - 1]));
  gy = static_cast<std::int16_t>((down[x - 1] + 2 * down[x] + down[x + 1]) -
                                 (up[x - 1] + 2 * up[x] + up[x + 1]));
  l1 = static_cast<std::int16_t>((gx < 0 ? -gx : gx) + (gy < 0 ? -gy : gy));
}

// One output row of the strongest-channel Sobel gradient from three rows (above, this, below)
// of the B, G and R planes; every row readable at [-1, n]. Integer arithmetic and selects only,
// so the compiler vectorises it (and the AVX2 copy gives the same bits). Ties keep the earlier
// channel (B, then G, then R).
SB_AVX2_CLONE void strongest_sobel_row(
    const std::uint8_t* __restrict b0, const std::uint8_t* __restrict b1,
    const std::uint8_t* __restrict b2, const std::uint8_t* __restrict g0,
    const std::uint8_t* __restrict g1, const std::uint8_t* __restrict g2,
    const std::uint8_t* __restrict r0, const std::uint8_t* __restrict r1,
    const std::uint8_t* __restrict r2, short* __restrict dx, short* __restrict dy, int n) {
  for (int x = 0; x < n; ++x) {
    std::int16_t bx, by, bm, gx, gy, gm, rx, ry, rm;
    sobel_at(b0, b1, b2, x, bx, by, bm);
    sobel_at(g0, g1, g2, x, gx, gy, gm);
    sobel_at(r0, r1, r2, x, rx, ry, rm);
    const bool take_g = gm > bm;
    const std::int16_t best = take_g ? gm : bm;
    std::int16_t sx = take_g ? gx : bx;
    std::int16_t sy = take_g ? gy : by;
    const bool take_r = rm > best;
    sx = take_r ? rx : sx;
    sy = take_r ? ry : sy;
    dx[x] = sx;
    dy[x] = sy;
  }
}

#if SB_HAVE_AVX2_KERNELS
// Sixteen bytes from p, each widened to 16 bits.
SB_TARGET_AVX2 inline __m256i widen_16(const std::uint8_t* p) {
  return _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
}

// sobel_at for the sixteen pixels from column x, in 16-bit lanes (the same integer sums).
SB_TARGET_AVX2 inline void sobel_16(const std::uint8_t* up, const std::uint8_t* mid,
                                    const std::uint8_t* down, int x, __m256i& gx, __m256i& gy,
                                    __m256i& l1) {
  const __m256i u0 = widen_16(up + x - 1), u1 = widen_16(up + x), u2 = widen_16(up + x + 1);
  const __m256i d0 = widen_16(down + x - 1), d1 = widen_16(down + x), d2 = widen_16(down + x + 1);
  const __m256i across = _mm256_sub_epi16(widen_16(mid + x + 1), widen_16(mid + x - 1));
  const __m256i along = _mm256_sub_epi16(d1, u1);
  gx = _mm256_add_epi16(_mm256_add_epi16(_mm256_sub_epi16(u2, u0), _mm256_sub_epi16(d2, d0)),
                        _mm256_add_epi16(across, across));
  gy = _mm256_add_epi16(_mm256_add_epi16(_mm256_sub_epi16(d0, u0), _mm256_sub_epi16(d2, u2)),
                        _mm256_add_epi16(along, along));
  l1 = _mm256_add_epi16(_mm256_abs_epi16(gx), _mm256_abs_epi16(gy));
}

// strongest_sobel_row sixteen pixels per step, written by hand: the compiler's copy widens
// 32-byte loads with extracts and spills. Rows narrower than a step: the plain loop.
SB_TARGET_AVX2 void strongest_sobel_row_avx2(const std::uint8_t* b0, const std::uint8_t* b1,
                                             const std::uint8_t* b2, const std::uint8_t* g0,
                                             const std::uint8_t* g1, const std::uint8_t* g2,
                                             const std::uint8_t* r0, const std::uint8_t* r1,
                                             const std::uint8_t* r2, short* dx, short* dy, int n) {
  if (n < 16) {
    strongest_sobel_row(b0, b1, b2, g0, g1, g2, r0, r1, r2, dx, dy, n);
    return;
  }
  // The last step ends at the row's end, overlapping the one before (it writes the same values).
  for (int x = 0;; x = std::min(x + 16, n - 16)) {
    __m256i bx, by, bm, gx, gy, gm, rx, ry, rm;
    sobel_16(b0, b1, b2, x, bx, by, bm);
    sobel_16(g0, g1, g2, x, gx, gy, gm);
    sobel_16(r0, r1, r2, x, rx, ry, rm);
    // Ties keep the earlier channel: strictly greater replaces.
    const __m256i take_g = _mm256_cmpgt_epi16(gm, bm);
    const __m256i take_r = _mm256_cmpgt_epi16(rm, _mm256_max_epi16(gm, bm));
    const __m256i sx = _mm256_blendv_epi8(_mm256_blendv_epi8(bx, gx, take_g), rx, take_r);
    const __m256i sy = _mm256_blendv_epi8(_mm256_blendv_epi8(by, gy, take_g), ry, take_r);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(dx + x), sx);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(dy + x), sy);
    if (x == n - 16) break;
  }
}
#endif

// strongest_sobel_row, with the hand-written AVX2 loop where the CPU has it.
void strongest_sobel(const std::uint8_t* b0, const std::uint8_t* b1, const std::uint8_t* b2,
                     const std::uint8_t* g0, const std::uint8_t* g1, const std::uint8_t* g2,
                     const std::uint8_t* r0, const std::uint8_t* r1, const std::uint8_t* r2,
                     short* dx, short* dy, int n) {
#if SB_HAVE_AVX2_KERNELS
  if (cpu_has_avx2()) {
    strongest_sobel_row_avx2(b0, b1, b2, g0, g1, g2, r0, r1, r2, dx, dy, n);
    return;
  }
#endif
  strongest_sobel_row(b0, b1, b2, g0, g1, g2, r0, r1, r2, dx, dy, n);
}

// One BGR row into three planes.
SB_AVX2_CLONE void split_row(const std::uint8_t* __restrict bgr, std::uint8_t* __restrict b,
                             std::uint8_t* __restrict g, std::uint8_t* __restrict r, int n) {
  for (int x = 0; x < n; ++x) {
    b[x] = bgr[3 * x];
    g[x] = bgr[3 * x + 1];
    r[x] = bgr[3 * x + 2];
  }
}

// Whether pixels [from, n) of a BGR row all have B == G == R.
bool row_channels_equal(const std::uint8_t* row, int from, int n) {
  unsigned diff = 0;
  for (const std::uint8_t* p = row + 3 * from; p < row + 3 * n; p += 3)
    diff |= (p[0] ^ p[1]) | (p[0] ^ p[2]);
  return diff == 0;
}

#if SB_HAVE_AVX2_KERNELS
// row_channels_equal 32 bytes at a time: each byte compared with the next, the comparisons
// wanted those at a pixel's B and G (B == G, G == R), whose bits repeat every three vectors.
SB_TARGET_AVX2 bool row_channels_equal_avx2(const std::uint8_t* row, int n) {
  constexpr auto wanted_from = [](int offset) {
    std::uint32_t bits = 0;
    for (int i = 0; i < 32; ++i)
      if ((offset + i) % 3 != 2) bits |= std::uint32_t{1} << i;
    return bits;
  };
  constexpr std::array<std::uint32_t, 3> wanted = {wanted_from(0), wanted_from(32),
                                                   wanted_from(64)};
  const int bytes = 3 * n;
  int i = 0;
  for (int phase = 0; i + 33 <= bytes; i += 32, phase = phase == 2 ? 0 : phase + 1) {
    const __m256i here = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(row + i));
    const __m256i next = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(row + i + 1));
    const auto same =
        static_cast<std::uint32_t>(_mm256_movemask_epi8(_mm256_cmpeq_epi8(here, next)));
    if ((same & wanted[static_cast<std::size_t>(phase)]) != wanted[static_cast<std::size_t>(phase)])
      return false;
  }
  // Every pixel whose B and G bytes lie before byte i is tested; the rest one by one.
  return row_channels_equal(row, i / 3, n);
}
#endif

}  // namespace

bool channels_equal(const cv::Mat& bgr) {
  CV_Assert(bgr.type() == CV_8UC3);
  for (int y = 0; y < bgr.rows; ++y) {
    const std::uint8_t* p = bgr.ptr<std::uint8_t>(y);
#if SB_HAVE_AVX2_KERNELS
    if (cpu_has_avx2()) {
      if (!row_channels_equal_avx2(p, bgr.cols)) return false;
      continue;
    }
#endif
    if (!row_channels_equal(p, 0, bgr.cols)) return false;
  }
  return true;
}

namespace {

// Where colour_gradient_rows reads a colour image's planes: the plane column and row of the
// image's first pixel less one (the crop's parent pixels around it); grey: the image was grey
// read as colour, and its whole gradient is made already.
struct ColourPlanes {
  int left = 0, top = 0;
  bool grey = false;
};

ColourPlanes colour_planes(const cv::Mat& bgr, cv::Mat& dx, cv::Mat& dy,
                           std::array<cv::Mat, 3>& planes);

// Rows first, first + step, ... (below end) of strongest_channel_gradient's dx, dy from
// colour_planes' planes (dx and dy made there).
void colour_gradient_rows(const cv::Mat& bgr, const ColourPlanes& at,
                          const std::array<cv::Mat, 3>& planes, int first, int end, int step,
                          cv::Mat& dx, cv::Mat& dy) {
  for (int y = first; y < end; y += step) {
    // Output row y is padded row y + top, plane row y + top + 1; its first pixel is column
    // left + 1 of the plane.
    const int py = y + at.top + 1;
    const auto row = [&](int c, int r) {
      return planes[static_cast<std::size_t>(c)].ptr<std::uint8_t>(py + r) + at.left + 1;
    };
    strongest_sobel(row(0, -1), row(0, 0), row(0, 1), row(1, -1), row(1, 0), row(1, 1), row(2, -1),
                    row(2, 0), row(2, 1), dx.ptr<short>(y), dy.ptr<short>(y), bgr.cols);
  }
}

}  // namespace

void strongest_channel_gradient(const cv::Mat& bgr, cv::Mat& dx, cv::Mat& dy,
                                std::array<cv::Mat, 3>& planes) {
  const ColourPlanes at = colour_planes(bgr, dx, dy, planes);
  if (!at.grey) colour_gradient_rows(bgr, at, planes, 0, bgr.rows, 1, dx, dy);
}

namespace {

ColourPlanes colour_planes(const cv::Mat& bgr, cv::Mat& dx, cv::Mat& dy,
                           std::array<cv::Mat, 3>& planes) {
  CV_Assert(bgr.type() == CV_8UC3);
  // A crop reads one pixel of its parent around it, as cv::Sobel does on a grey crop; past the
  // parent's border (or a whole image's) the outermost pixels repeat.
  cv::Size whole;
  cv::Point at;
  bgr.locateROI(whole, at);
  const int left = std::min(1, at.x), top = std::min(1, at.y);
  const int right = std::min(1, whole.width - at.x - bgr.cols);
  const int bottom = std::min(1, whole.height - at.y - bgr.rows);
  cv::Mat padded = bgr;
  if (left || top || right || bottom) padded.adjustROI(top, bottom, left, right);
  if (channels_equal(padded)) {
    // A grey image read as colour (common for photographs): every channel's gradient is the
    // same, and ties keep B, so B's Sobel alone gives the same bits at a third of the cost.
    // The crop keeps its one pixel of parent around it as a ROI of the extracted plane.
    cv::extractChannel(padded, planes[0], 0);
    grey_sobel(planes[0](cv::Rect(left, top, bgr.cols, bgr.rows)), dx, dy);
    return {left, top, true};
  }
  // Planes of the padded image with one more replicated pixel on every side: the row loop
  // then reads x - 1 and x + 1 everywhere without a border case.
  const int pw = padded.cols, ph = padded.rows;
  for (int c = 0; c < 3; ++c) planes[c].create(ph + 2, pw + 2, CV_8UC1);
  // Split by hand, row by row: cv::split and row copies cost more in call overhead than in
  // work on the small windows refinement asks for.
  for (int y = 0; y < ph; ++y) {
    std::uint8_t* b = planes[0].ptr<std::uint8_t>(y + 1);
    std::uint8_t* g = planes[1].ptr<std::uint8_t>(y + 1);
    std::uint8_t* r = planes[2].ptr<std::uint8_t>(y + 1);
    split_row(padded.ptr<std::uint8_t>(y), b + 1, g + 1, r + 1, pw);
    b[0] = b[1];
    g[0] = g[1];
    r[0] = r[1];
    b[pw + 1] = b[pw];
    g[pw + 1] = g[pw];
    r[pw + 1] = r[pw];
  }
  for (int c = 0; c < 3; ++c) {
    cv::Mat& p = planes[c];
    std::memcpy(p.ptr<std::uint8_t>(0), p.ptr<std::uint8_t>(1), static_cast<std::size_t>(pw + 2));
    std::memcpy(p.ptr<std::uint8_t>(ph + 1), p.ptr<std::uint8_t>(ph),
                static_cast<std::size_t>(pw + 2));
  }
  dx.create(bgr.size(), CV_16S);
  dy.create(bgr.size(), CV_16S);
  return {left, top, false};
}

}  // namespace

namespace {

void colour_sobel(EdgeMap& out) {
  strongest_channel_gradient(out.colour, out.dx, out.dy, out.colour_planes);
}

void sobel(EdgeMap& out) {
  if (!out.colour.empty())
    colour_sobel(out);
  else
    grey_sobel(out.grey, out.dx, out.dy);
}

void blur_and_sobel(EdgeMap& out) {
  cv::Mat smooth;
  cv::Mat& source = out.colour.empty() ? out.grey : out.colour;
  cv::GaussianBlur(source, smooth, cv::Size(5, 5), 1.2, 1.2, cv::BORDER_REPLICATE);
  source = smooth;
  sobel(out);
}

void canny_and_thin(const EdgeParams& params, const CannyThresholds& t, EdgeMap& out) {
  out.low_threshold = t.low;
  out.high_threshold = t.high;
  out.median_gradient = t.median_gradient;
  canny_l1(out.dx, out.dy, t.low, t.high, out.edges, out.canny_work);
  out.bits.assign(out.edges);
  out.removed_staircase = params.thin ? thin_staircase(out.edges, out.bits) : 0;
  list_edge_points(out.bits, out.dx, out.dy, out.points);
}

}  // namespace

cv::Rect2d frame_of(const cv::Mat& image) {
  cv::Size whole;
  cv::Point offset;
  image.locateROI(whole, offset);
  return cv::Rect2d(-offset.x, -offset.y, whole.width, whole.height);
}

namespace {

// Sets the image the gradient is taken of: the colour image, or grey.
void set_source(const cv::Mat& image, const EdgeParams& params, EdgeMap& out) {
  out.frame_px = frame_of(image);
  if (params.colour && image.type() == CV_8UC3) {
    out.colour = image;
    out.grey.release();
  } else if (params.colour && image.type() == CV_8UC4) {
    cv::cvtColor(image, out.colour, cv::COLOR_BGRA2BGR);
    out.grey.release();
  } else {
    out.colour.release();
    out.grey = to_grey(image);
  }
}

}  // namespace

namespace {

// The even bits of v (bits 0, 2, ..., 62) packed into its low 32 bits, in order.
std::uint64_t even_bits(std::uint64_t v) {
  v &= 0x5555555555555555ULL;
  v = (v | v >> 1) & 0x3333333333333333ULL;
  v = (v | v >> 2) & 0x0F0F0F0F0F0F0F0FULL;
  v = (v | v >> 4) & 0x00FF00FF00FF00FFULL;
  v = (v | v >> 8) & 0x0000FFFF0000FFFFULL;
  return (v | v >> 16) & 0x00000000FFFFFFFFULL;
}

// bits halved into half (reset to w x h): each pixel the OR of its 2 x 2 block, a word of 64
// pixels from two words of each of the block's rows.
void halve_bits(const BitImage& bits, int w, int h, BitImage& half) {
  half.reset(w, h);
  const int in_words = (bits.width() + 63) / 64, out_words = (w + 63) / 64;
  // The last word holds only pixels of [0, w): a dropped odd column would land past it.
  const std::uint64_t last_mask =
      w % 64 == 0 ? ~std::uint64_t{0} : (std::uint64_t{1} << (w % 64)) - 1;
  for (int y = 0; y < h; ++y) {
    const std::uint64_t* a = bits.row(2 * y);
    const std::uint64_t* b = bits.row(2 * y + 1);
    std::uint64_t* out = half.mutable_row(y);
    for (int wo = 0; wo < out_words; ++wo) {
      std::uint64_t word = 0;
      for (int part = 0; part < 2; ++part) {
        const int wi = 2 * wo + part;
        if (wi >= in_words) break;
        const std::uint64_t both = a[wi] | b[wi];
        word |= even_bits(both | both >> 1) << (32 * part);
      }
      out[wo] = wo == out_words - 1 ? word & last_mask : word;
    }
  }
}

// Outputs [from, to) of halve_derivative's row (a, b: the block's two rows).
void halve_derivative_row(const short* a, const short* b, short* out, int from, int to) {
  for (int x = from; x < to; ++x)
    out[x] = cv::saturate_cast<short>(a[2 * x] + a[2 * x + 1] + b[2 * x] + b[2 * x + 1]);
}

#if SB_HAVE_AVX2_KERNELS
// The 8 block sums of a's and b's 16 derivatives at once, in 32 bits (madd with ones: exact).
SB_TARGET_AVX2 inline __m256i block_sums(const short* a, const short* b) {
  const __m256i ones = _mm256_set1_epi16(1);
  const __m256i va = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(a));
  const __m256i vb = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b));
  return _mm256_add_epi32(_mm256_madd_epi16(va, ones), _mm256_madd_epi16(vb, ones));
}

// halve_derivative_row 16 outputs a step: the sums packed with the same saturation; packs
// interleaves the lanes, the permute puts them back in order.
SB_TARGET_AVX2 void halve_derivative_row_avx2(const short* a, const short* b, short* out, int w) {
  int x = 0;
  for (; x + 16 <= w; x += 16) {
    const __m256i packed = _mm256_packs_epi32(block_sums(a + 2 * x, b + 2 * x),
                                              block_sums(a + 2 * x + 16, b + 2 * x + 16));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + x),
                        _mm256_permute4x64_epi64(packed, 0xD8));
  }
  halve_derivative_row(a, b, out, x, w);
}
#endif

// The 2 x 2 block sums of a CV_16S derivative into half (w x h, saturated).
void halve_derivative(const cv::Mat& full, int w, int h, cv::Mat& half) {
  half.create(h, w, CV_16S);
  for (int y = 0; y < h; ++y) {
    const short* a = full.ptr<short>(2 * y);
    const short* b = full.ptr<short>(2 * y + 1);
    short* out = half.ptr<short>(y);
#if SB_HAVE_AVX2_KERNELS
    if (cpu_has_avx2()) {
      halve_derivative_row_avx2(a, b, out, w);
      continue;
    }
#endif
    halve_derivative_row(a, b, out, 0, w);
  }
}

}  // namespace

void halve_edge_map(const EdgeMap& full, const cv::Mat& half_image, bool thin, EdgeMap& half) {
  const int w = full.edges.cols / 2, h = full.edges.rows / 2;
  halve_bits(full.bits, w, h, half.bits);
  half.edges.create(h, w, CV_8UC1);
  half.edges.setTo(0);
  for (int y = 0; y < h; ++y) {
    uchar* row = half.edges.ptr<uchar>(y);
    half.bits.for_each_set_in_row(y, [&](int x) { row[x] = 255; });
  }
  halve_derivative(full.dx, w, h, half.dx);
  halve_derivative(full.dy, w, h, half.dy);
  // As the edge step leaves its map: thinned, with a clear frame.
  half.removed_staircase = 0;
  if (thin) {
    half.removed_staircase = thin_staircase(half.edges, half.bits);
  } else if (w >= 1 && h >= 1) {
    clear_frame(half.edges);
    half.bits.assign(half.edges);
  }
  list_edge_points(half.bits, half.dx, half.dy, half.points);
  half.low_threshold = full.low_threshold;
  half.high_threshold = full.high_threshold;
  half.median_gradient = full.median_gradient;
  half.denoised = full.denoised;
  // As the halved image's own frame (reduce_image drops an odd last row or column).
  half.frame_px =
      cv::Rect2d(0.5 * full.frame_px.x, 0.5 * full.frame_px.y,
                 std::floor(0.5 * full.frame_px.width), std::floor(0.5 * full.frame_px.height));
  if (!full.colour.empty() && half_image.type() == CV_8UC3) {
    half.colour = half_image;
    half.grey.release();
  } else {
    half.colour.release();
    half.grey = half_image.empty() ? cv::Mat() : to_grey(half_image);
  }
}

void list_edge_points(const BitImage& bits, const cv::Mat& dx, const cv::Mat& dy, EdgePoints& out) {
  // Counted first, so the arrays are sized once and filled by index (no growth checks).
  const int h = bits.height(), words = (bits.width() + 63) / 64;
  out.row_start.resize(static_cast<std::size_t>(h) + 1);
  int total = 0;
  for (int y = 0; y < h; ++y) {
    out.row_start[static_cast<std::size_t>(y)] = total;
    const std::uint64_t* r = bits.row(y);
    for (int wi = 0; wi < words; ++wi) total += std::popcount(r[wi]);
  }
  out.row_start.back() = total;
  const auto n = static_cast<std::size_t>(total);
  out.x.resize(n);
  out.y.resize(n);
  out.gx.resize(n);
  out.gy.resize(n);
  std::size_t i = 0;
  for (int y = 0; y < h; ++y) {
    const short* gx = dx.ptr<short>(y);
    const short* gy = dy.ptr<short>(y);
    bits.for_each_set_in_row(y, [&](int x) {
      out.x[i] = x;
      out.y[i] = y;
      out.gx[i] = gx[x];
      out.gy[i] = gy[x];
      ++i;
    });
  }
}

namespace {

// The unblurred colour gradient's thresholds and whether it calls for the pre-blur, made row by
// row: the sampled rows first, counted as they come, and the decision taken as soon as they
// settle it. Only a gradient kept (no pre-blur) gets its other rows. dx, dy made by
// colour_planes.
EdgeThresholds colour_thresholds(const ColourPlanes& planes, const EdgeParams& params,
                                 EdgeMap& work) {
  const cv::Mat& bgr = work.colour;
  const int total = sample_count(bgr.rows, bgr.cols);
  const bool may_blur = params.denoise_median > 0.0;
  SampledGradients samples;
  for (int y = 0; y < bgr.rows; y += kThresholdSampleStep) {
    colour_gradient_rows(bgr, planes, work.colour_planes, y, y + 1, 1, work.dx, work.dy);
    samples.add_row(work.dx.ptr<short>(y), work.dy.ptr<short>(y), bgr.cols);
    // A noisy image's median is settled long before its last row.
    if (may_blur && samples.median_above(params.denoise_median, total)) return {{}, true};
  }
  const CannyThresholds t = samples.thresholds(params);
  if (may_blur && t.median_gradient > params.denoise_median) return {t, true};
  for (int first = 1; first < kThresholdSampleStep; ++first)
    colour_gradient_rows(bgr, planes, work.colour_planes, first, bgr.rows, kThresholdSampleStep,
                         work.dx, work.dy);
  return {t, false};
}

}  // namespace

EdgeThresholds measure_edge_thresholds(const cv::Mat& image, const EdgeParams& params,
                                       EdgeMap& work) {
  set_source(image, params, work);
  EdgeThresholds t;
  ColourPlanes planes;
  if (!work.colour.empty())
    planes = colour_planes(work.colour, work.dx, work.dy, work.colour_planes);
  if (!work.colour.empty() && !planes.grey) {
    t = colour_thresholds(planes, params, work);
  } else {
    if (work.colour.empty()) sobel(work);  // grey read as colour: made by colour_planes
    t.canny = canny_thresholds(work.dx, work.dy, params);
    t.denoise = params.denoise_median > 0.0 && t.canny.median_gradient > params.denoise_median;
  }
  work.denoised = t.denoise;
  if (work.denoised) {
    // Heavy noise: Canny alone would chain noise pixels into edges; blur once and redo.
    blur_and_sobel(work);
    t.canny = canny_thresholds(work.dx, work.dy, params);
  }
  return t;
}

void compute_edge_map(const cv::Mat& image, const EdgeParams& params, EdgeMap& out) {
  const EdgeThresholds t = measure_edge_thresholds(image, params, out);
  canny_and_thin(params, t.canny, out);
}

void compute_edge_map(const cv::Mat& image, const EdgeParams& params, const CannyThresholds& fixed,
                      bool denoise, EdgeMap& out) {
  set_source(image, params, out);
  out.denoised = denoise;
  if (out.denoised) {
    blur_and_sobel(out);
  } else {
    sobel(out);
  }
  canny_and_thin(params, fixed, out);
}

void remove_brightness(const cv::Mat& bgr, cv::Mat& out) {
  CV_Assert(bgr.type() == CV_8UC3);
  out.create(bgr.size(), CV_8UC3);
  for (int y = 0; y < bgr.rows; ++y)
    brightness_free_row(bgr.ptr<std::uint8_t>(y), out.ptr<std::uint8_t>(y), bgr.cols);
}

void compute_brightness_free_edge_map(const cv::Mat& bgr, const EdgeParams& params,
                                      cv::Mat& scratch, EdgeMap& out) {
  remove_brightness(bgr, scratch);
  compute_edge_map(scratch, params, out);
  out.frame_px = frame_of(bgr);
}

void compute_brightness_free_edge_map(const cv::Mat& bgr, const EdgeParams& params,
                                      const CannyThresholds& fixed, bool denoise, cv::Mat& scratch,
                                      EdgeMap& out) {
  remove_brightness(bgr, scratch);
  compute_edge_map(scratch, params, fixed, denoise, out);
  out.frame_px = frame_of(bgr);
}

}  // namespace stereoball::ball_detector
