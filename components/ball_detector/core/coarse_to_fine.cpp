#include "ball_detector/core/coarse_to_fine.hpp"

#include "ball_detector/core/cpu_dispatch.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

#if SB_HAVE_AVX2_KERNELS
#include <immintrin.h>
#endif

namespace stereoball::ball_detector {

Status CoarseToFineParams::validate() const {
  if (target_width_px < 0 || target_width_px > 16384)
    return Error{"target_width_px must be in [0, 16384]"};
  if (!(min_coarse_radius_px > 0.0 && min_coarse_radius_px <= 1000.0))
    return Error{"min_coarse_radius_px must be in (0, 1000]"};
  if (max_level < 0 || max_level > 4) return Error{"max_level must be in [0, 4]"};
  if (!(max_refine_shift >= 0.0 && max_refine_shift <= 1.0))
    return Error{"max_refine_shift must be in [0, 1]"};
  return {};
}

int coarse_level(int image_width_px, const CoarseToFineParams& params) {
  if (params.target_width_px <= 0 || image_width_px <= params.target_width_px) return 0;
  const double ratio = static_cast<double>(image_width_px) / params.target_width_px;
  const int level = static_cast<int>(std::lround(std::log2(ratio)));
  return std::clamp(level, 0, params.max_level);
}

RadiusSplit split_radius_range(const RadiusRange& full, int level, double min_coarse_radius_px) {
  RadiusSplit out;
  if (level <= 0) {
    out.fine_px = full;
    return out;
  }
  const double scale = std::ldexp(1.0, level);
  // The smallest radius the reduced image still resolves, in full-resolution pixels.
  const double limit_px = min_coarse_radius_px * scale;
  if (full.max_px >= limit_px)
    out.coarse_px = RadiusRange{std::max(full.min_px, limit_px) / scale, full.max_px / scale};
  if (full.min_px < limit_px)
    out.fine_px = RadiusRange{full.min_px, std::min(full.max_px, limit_px)};
  return out;
}

PixelToPixelParams params_at_level(const PixelToPixelParams& full, int level) {
  if (level <= 0) return full;
  const int scale = 1 << level;
  const double f = 1.0 / scale;
  PixelToPixelParams p = full;
  p.coarse_to_fine = false;
  p.k_values.clear();
  for (int k : full.k_values)
    if (const int reduced = std::max(1, (k + scale - 1) / scale);
        std::find(p.k_values.begin(), p.k_values.end(), reduced) == p.k_values.end())
      p.k_values.push_back(reduced);
  p.min_radius_px = full.min_radius_px * f;
  p.max_radius_px = full.max_radius_px * f;
  p.min_separation_px = full.min_separation_px * f;
  p.refine_params.clutter_min_radius_px = full.refine_params.clutter_min_radius_px * f;
  // An outline has 2^level times fewer edge points to vote with.
  p.min_peak_votes = std::max(1, (full.min_peak_votes + scale - 1) / scale);
  // Every examined peak goes on to full resolution, where the best max_circles are kept; a
  // candidate a little below min_score here may reach it on the sharper edges.
  p.max_circles = std::max(full.max_circles, full.max_peaks_examined);
  p.min_score = std::min(full.min_score, full.coarse_min_score);
  p.refine_params.give_up_below = std::min(full.refine_params.give_up_below, p.min_score);
  p.polish = false;  // the full-resolution refinement polishes
  p.refine_params.camera.reset();
  // Clutter is judged at full resolution, where the rings are measured on sharper edges.
  p.refine_params.clutter_ring_per_radius = 0.0;
  return p;
}

void reduce_image(const cv::Mat& image, int level, cv::Mat& out) {
  if (level <= 0) {
    out = image;
    return;
  }
  const int scale = 1 << level;
  const cv::Mat even =
      image(cv::Rect(0, 0, image.cols / scale * scale, image.rows / scale * scale));
  // INTER_AREA by a whole factor: each pixel the mean of its block.
  cv::resize(even, out, cv::Size(even.cols / scale, even.rows / scale), 0.0, 0.0, cv::INTER_AREA);
}

namespace {

// halve_image's rounded block mean of output bytes [from, to) of a row of cn channels (a, b: the
// two input rows).
void halve_bytes(const std::uint8_t* a, const std::uint8_t* b, std::uint8_t* out, int cn, int from,
                 int to) {
  for (int j = from; j < to; ++j) {
    const int i = 2 * (j - j % cn) + j % cn;  // the block's first pixel, same channel
    out[j] = static_cast<std::uint8_t>((a[i] + a[i + cn] + b[i] + b[i + cn] + 2) >> 2);
  }
}

#if SB_HAVE_AVX2_KERNELS
// Sums of adjacent bytes of 32 at p, in pairs (maddubs with ones).
SB_TARGET_AVX2 inline __m256i pair_sums(const std::uint8_t* p) {
  return _mm256_maddubs_epi16(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)),
                              _mm256_set1_epi8(1));
}

// (pair sums of a + pair sums of b + 2) >> 2: the rounded block means, one per 16-bit lane.
SB_TARGET_AVX2 inline __m256i rounded_quarter(__m256i sums_a, __m256i sums_b) {
  return _mm256_srli_epi16(_mm256_add_epi16(_mm256_add_epi16(sums_a, sums_b), _mm256_set1_epi16(2)),
                           2);
}

// One byte per pixel: 32 outputs a step.
SB_TARGET_AVX2 void halve_row_grey_avx2(const std::uint8_t* a, const std::uint8_t* b,
                                        std::uint8_t* out, int bytes) {
  int j = 0;
  for (; j + 32 <= bytes; j += 32) {
    const __m256i lo = rounded_quarter(pair_sums(a + 2 * j), pair_sums(b + 2 * j));
    const __m256i hi = rounded_quarter(pair_sums(a + 2 * j + 32), pair_sums(b + 2 * j + 32));
    // packus interleaves the lanes: the quarters put back in order.
    const __m256i packed = _mm256_permute4x64_epi64(_mm256_packus_epi16(lo, hi), 0xD8);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + j), packed);
  }
  halve_bytes(a, b, out, 1, j, bytes);
}

// Same-channel sums of adjacent pixels of the 8 BGR pixels at p (bytes p .. p + 23), 6 per lane:
// each 12-byte group of four pixels shuffled into pairs, then summed (maddubs with ones).
SB_TARGET_AVX2 inline __m256i bgr_pair_sums(const std::uint8_t* p) {
  const __m256i pairs = _mm256_setr_epi8(0, 3, 1, 4, 2, 5, 6, 9, 7, 10, 8, 11, -1, -1, -1, -1, 0, 3,
                                         1, 4, 2, 5, 6, 9, 7, 10, 8, 11, -1, -1, -1, -1);
  const __m256i v = _mm256_loadu2_m128i(reinterpret_cast<const __m128i*>(p + 12),
                                        reinterpret_cast<const __m128i*>(p));
  return _mm256_maddubs_epi16(_mm256_shuffle_epi8(v, pairs), _mm256_set1_epi8(1));
}

// Three bytes per pixel: 24 outputs a step. Each step writes 4 bytes past its outputs (the next
// step's) and reads 4 past its 48 inputs, so it runs only while 28 outputs fit.
SB_TARGET_AVX2 void halve_row_bgr_avx2(const std::uint8_t* a, const std::uint8_t* b,
                                       std::uint8_t* out, int bytes) {
  const __m256i gather = _mm256_setr_epi8(0, 1, 2, 3, 4, 5, 8, 9, 10, 11, 12, 13, -1, -1, -1, -1, 0,
                                          1, 2, 3, 4, 5, 8, 9, 10, 11, 12, 13, -1, -1, -1, -1);
  int j = 0;
  for (; j + 28 <= bytes; j += 24) {
    const __m256i first = rounded_quarter(bgr_pair_sums(a + 2 * j), bgr_pair_sums(b + 2 * j));
    const __m256i second =
        rounded_quarter(bgr_pair_sums(a + 2 * j + 24), bgr_pair_sums(b + 2 * j + 24));
    // Lane by lane: outputs 0-5 | 6-11 of first, 12-17 | 18-23 of second, each with two zeros.
    const __m256i ordered = _mm256_shuffle_epi8(
        _mm256_permute4x64_epi64(_mm256_packus_epi16(first, second), 0xD8), gather);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + j), _mm256_castsi256_si128(ordered));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + j + 12),
                     _mm256_extracti128_si256(ordered, 1));
  }
  halve_bytes(a, b, out, 3, j, bytes);
}
#endif

}  // namespace

void halve_image(const cv::Mat& even, cv::Mat& half) {
  const cv::Size size(even.cols / 2, even.rows / 2);
#if SB_HAVE_AVX2_KERNELS
  const int cn = even.channels();
  if (cpu_has_avx2() && even.depth() == CV_8U && (cn == 1 || cn == 3) && even.cols % 2 == 0 &&
      even.rows % 2 == 0 && !even.empty()) {
    half.create(size, even.type());
    for (int y = 0; y < size.height; ++y) {
      const std::uint8_t* a = even.ptr<std::uint8_t>(2 * y);
      const std::uint8_t* b = even.ptr<std::uint8_t>(2 * y + 1);
      if (cn == 1)
        halve_row_grey_avx2(a, b, half.ptr<std::uint8_t>(y), size.width);
      else
        halve_row_bgr_avx2(a, b, half.ptr<std::uint8_t>(y), 3 * size.width);
    }
    return;
  }
#endif
  // INTER_AREA by two: each pixel the rounded mean of its block.
  cv::resize(even, half, size, 0.0, 0.0, cv::INTER_AREA);
}

Circle to_full_resolution(const Circle& reduced, int level) {
  const double scale = std::ldexp(1.0, level);
  // Pixel i of the reduced image is the mean of pixels scale*i .. scale*i + scale - 1.
  const double offset = 0.5 * (scale - 1.0);
  return Circle{scale * reduced.x_px + offset, scale * reduced.y_px + offset,
                scale * reduced.radius_px, reduced.score};
}

bool holds_seed(const Circle& refined, const Circle& seed, double max_shift) {
  if (!(max_shift > 0.0)) return true;
  const double r = std::max(seed.radius_px, 1.0);
  return std::hypot(refined.x_px - seed.x_px, refined.y_px - seed.y_px) <= max_shift * r &&
         std::abs(refined.radius_px - seed.radius_px) <= max_shift * r;
}

std::vector<Circle> refine_coarse_circles(const PixelToPixelDetector& fine,
                                          std::span<const Circle> reduced, int level,
                                          double max_shift) {
  std::vector<Circle> seeds;
  seeds.reserve(reduced.size());
  for (const Circle& c : reduced) seeds.push_back(to_full_resolution(c, level));
  if (!(max_shift > 0.0)) return fine.refine_seeds(seeds);
  // Each seed on its own, so a refined circle is compared with the seed it came from; those
  // that hold are ranked and separated as refine_seeds() would, without refining them again
  // (a second refinement moved a held circle by a fraction of a pixel at twice the cost).
  std::vector<Circle> held;
  for (const Circle& seed : seeds) {
    const std::vector<Circle> one = fine.refine_seeds(std::span<const Circle>(&seed, 1));
    if (!one.empty() && holds_seed(one.front(), seed, max_shift)) held.push_back(one.front());
  }
  return fine.keep_best_separated(std::move(held));
}

}  // namespace stereoball::ball_detector
