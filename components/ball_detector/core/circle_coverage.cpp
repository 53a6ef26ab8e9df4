// What lies around a centre: the angular coverage of a circle by points (sectors of about 3 px
// of circumference, in the whole image or in the part of it inside the frame) and the radius
// whose ring of radial edge points is densest (estimate_radius, plain and AVX2 counts). Apart
// from the refinement (circle_refine.cpp): robust_outline.cpp scores with the coverage too, and
// the peak circles' ring seed comes from estimate_radius.
#include "ball_detector/core/circle_fit.hpp"

#include "ball_detector/core/cpu_dispatch.hpp"
#include "ball_detector/core/fast_math.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace stereoball::ball_detector {
namespace {

constexpr int kMaxSectors = 180;  // sector_count's largest

// About one sector per 3 px of circumference: adjacent edge pixels fill a sector, a gap of a
// few pixels shows.
int sector_count(const Circle& c) {
  return std::clamp(static_cast<int>(2.0 * std::numbers::pi * c.radius_px / 3.0), 8, kMaxSectors);
}

// Sector s spans angles [s, s + 1) * 2 pi / sectors - pi around the centre.
int exact_sector(double dy, double dx, int sectors) {
  const double a = std::atan2(dy, dx) + std::numbers::pi;
  return std::min(sectors - 1, static_cast<int>(a / (2.0 * std::numbers::pi) * sectors));
}

// atan(z) for z in [0, 1] by an odd polynomial (Abramowitz and Stegun 4.4.49); measured on 2e8
// evenly spaced z: |error| < 4e-8 rad.
inline double atan_unit(double z) {
  const double z2 = z * z;
  return z * (0.9999993329 +
              z2 * (-0.3332985605 +
                    z2 * (0.1994653599 +
                          z2 * (-0.1390853351 +
                                z2 * (0.0964200441 +
                                      z2 * (-0.0559098861 +
                                            z2 * (0.0218612288 + z2 * -0.0040540580)))))));
}

// exact_sector without atan2 for the points not near a sector boundary. The polynomial's angle
// is within 1e-7 rad of the true one (4e-8 and the rounding of the reduction), at most 3e-6 of
// a sector (180 sectors); a point whose approximate place in its sector is more than
// kSectorMargin (1e-4 of a sector) from either boundary lies in that sector, and exact_sector,
// exact to a few ulps, puts it there too. The others (and the centre itself, and the wrap at
// +-pi) take exact_sector: the same sector for every point.
constexpr double kSectorMargin = 1e-4;
inline int sector_of_offset(double dy, double dx, int sectors) {
  const double ax = std::abs(dx), ay = std::abs(dy);
  const double hi = std::max(ax, ay);
  if (hi > 0.0) {
    double a = atan_unit(std::min(ax, ay) / hi);
    if (ay > ax) a = 0.5 * std::numbers::pi - a;
    if (dx < 0.0) a = std::numbers::pi - a;
    if (dy < 0.0) a = -a;
    const double u = (a + std::numbers::pi) * (sectors / (2.0 * std::numbers::pi));
    const int s = static_cast<int>(u);
    const double frac = u - s;
    if (frac > kSectorMargin && frac < 1.0 - kSectorMargin && s < sectors) return s;
  }
  return exact_sector(dy, dx, sectors);
}

int sector_of(const Circle& c, const cv::Point2d& p, int sectors) {
  return sector_of_offset(p.y - c.y_px, p.x - c.x_px, sectors);
}

}  // namespace

double angular_coverage(const Circle& c, std::span<const cv::Point2d> points) {
  const int sectors = sector_count(c);
  std::array<unsigned char, kMaxSectors> hit{};
  for (const auto& p : points) hit[static_cast<std::size_t>(sector_of(c, p, sectors))] = 1;
  return static_cast<double>(std::count(hit.begin(), hit.begin() + sectors, 1)) / sectors;
}

double angular_coverage_in_frame(const Circle& c, std::span<const cv::Point2d> points,
                                 const cv::Rect2d& frame, double min_inside,
                                 const OutlineStretch& stretch) {
  const int sectors = sector_count(c);
  std::array<unsigned char, kMaxSectors> inside{};
  int inside_count = 0;
  // The outline lies within ratio * r of the centre: when that square, a pixel wider for
  // rounding, is in the frame, every sector is, without a sine and cosine each.
  const double reach = stretch.ratio * c.radius_px + 1.0;
  const bool all_inside = c.x_px - reach >= frame.x + 1.0 && c.y_px - reach >= frame.y + 1.0 &&
                          c.x_px + reach <= frame.x + frame.width - 2.0 &&
                          c.y_px + reach <= frame.y + frame.height - 2.0;
  if (all_inside) {
    std::fill(inside.begin(), inside.begin() + sectors, 1);
    inside_count = sectors;
  }
  for (int s = 0; s < sectors && !all_inside; ++s) {
    const double a = (s + 0.5) * 2.0 * std::numbers::pi / sectors - std::numbers::pi;
    const cv::Point2d on_outline =
        stretch.from_round({c.radius_px * std::cos(a), c.radius_px * std::sin(a)});
    const double x = c.x_px + on_outline.x, y = c.y_px + on_outline.y;
    // One pixel in from the border: Sobel has no full neighbourhood on the outermost row.
    if (x >= frame.x + 1.0 && y >= frame.y + 1.0 && x <= frame.x + frame.width - 2.0 &&
        y <= frame.y + frame.height - 2.0) {
      inside[s] = 1;
      ++inside_count;
    }
  }
  if (inside_count == 0 || inside_count < min_inside * sectors) return 0.0;
  std::array<unsigned char, kMaxSectors> hit{};
  for (const auto& p : points) {
    const auto s = static_cast<std::size_t>(sector_of(c, p, sectors));
    hit[s] = inside[s];
  }
  return static_cast<double>(std::count(hit.begin(), hit.begin() + sectors, 1)) / inside_count;
}

namespace {

// estimate_radius's ring of a point: the bin its distance from (cx, cy) rounds to, if that is
// in [r0, r1] and its gradient is about radial, else discard.
struct RingBinner {
  double cx, cy;
  int r0, r1, discard;

  int bin_of(int x, int y, double gx, double gy) const {
    const double rx = x - cx, ry = y - cy;
    const double d2 = rx * rx + ry * ry;
    const int bin = static_cast<int>(std::sqrt(d2) + 0.5);  // lround of a distance >= 0
    // Loose radial test, |g . r| >= 0.7 |g| |r|, squared (no roots): the centre is only known
    // to a pixel or two here.
    const double g_dot_r = gx * rx + gy * ry;
    const double g2 = gx * gx + gy * gy;
    const bool counts = (bin >= r0) & (bin <= r1) & !(g_dot_r * g_dot_r < 0.49 * g2 * d2);
    return counts ? bin : discard;
  }
};

// Counts points [begin, end) into hist by RingBinner (no branch on a point: whether one counts
// is a coin toss to the branch predictor).
void count_ring_bins(const EdgePoints& p, std::size_t begin, std::size_t end,
                     const RingBinner& binner, int* hist) {
  for (std::size_t i = begin; i < end; ++i) ++hist[binner.bin_of(p.x[i], p.y[i], p.gx[i], p.gy[i])];
}

#if SB_HAVE_AVX2_KERNELS
// count_ring_bins four points at a time: the same double operations in the same order (no
// fused multiply-add), so the same bins.
SB_TARGET_AVX2 void count_ring_bins_avx2(const EdgePoints& p, std::size_t begin, std::size_t end,
                                         const RingBinner& binner, int* hist) {
  const __m256d cx = _mm256_set1_pd(binner.cx), cy = _mm256_set1_pd(binner.cy);
  const __m256d half = _mm256_set1_pd(0.5), radial2 = _mm256_set1_pd(0.49);
  const __m128i below = _mm_set1_epi32(binner.r0 - 1), above = _mm_set1_epi32(binner.r1 + 1);
  const __m128i discard = _mm_set1_epi32(binner.discard);
  // The low 32 bits of each 64-bit compare mask, as four 32-bit lanes.
  const __m256i low_halves = _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6);
  std::size_t i = begin;
  alignas(16) int bins[4];
  for (; i + 4 <= end; i += 4) {
    const __m256d rx = _mm256_sub_pd(
        _mm256_cvtepi32_pd(_mm_loadu_si128(reinterpret_cast<const __m128i*>(&p.x[i]))), cx);
    const __m256d ry = _mm256_sub_pd(
        _mm256_cvtepi32_pd(_mm_loadu_si128(reinterpret_cast<const __m128i*>(&p.y[i]))), cy);
    const __m256d gx = _mm256_cvtepi32_pd(
        _mm_cvtepi16_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(&p.gx[i]))));
    const __m256d gy = _mm256_cvtepi32_pd(
        _mm_cvtepi16_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(&p.gy[i]))));
    const __m256d d2 = _mm256_add_pd(_mm256_mul_pd(rx, rx), _mm256_mul_pd(ry, ry));
    const __m128i bin = _mm256_cvttpd_epi32(_mm256_add_pd(_mm256_sqrt_pd(d2), half));
    const __m256d g_dot_r = _mm256_add_pd(_mm256_mul_pd(gx, rx), _mm256_mul_pd(gy, ry));
    const __m256d g2 = _mm256_add_pd(_mm256_mul_pd(gx, gx), _mm256_mul_pd(gy, gy));
    const __m256d off_radial = _mm256_cmp_pd(
        _mm256_mul_pd(g_dot_r, g_dot_r), _mm256_mul_pd(_mm256_mul_pd(radial2, g2), d2), _CMP_LT_OQ);
    const __m128i off32 = _mm256_castsi256_si128(
        _mm256_permutevar8x32_epi32(_mm256_castpd_si256(off_radial), low_halves));
    const __m128i in_range =
        _mm_and_si128(_mm_cmpgt_epi32(bin, below), _mm_cmpgt_epi32(above, bin));
    const __m128i counts = _mm_andnot_si128(off32, in_range);
    _mm_store_si128(reinterpret_cast<__m128i*>(bins), _mm_blendv_epi8(discard, bin, counts));
    ++hist[bins[0]];
    ++hist[bins[1]];
    ++hist[bins[2]];
    ++hist[bins[3]];
  }
  count_ring_bins(p, i, end, binner, hist);
}
#endif

}  // namespace

std::optional<double> estimate_radius(const EdgeMap& edges, double cx, double cy,
                                      double min_radius_px, double max_radius_px) {
  const int r0 = std::max(1, static_cast<int>(std::floor(min_radius_px)));
  const int r1 = static_cast<int>(std::ceil(max_radius_px));
  if (r1 <= r0) return std::nullopt;
  // Bins r0 - 1 ... r1 + 1 are read; points that do not count go to r1 + 2.
  std::vector<int> hist(r1 + 3, 0);
  // A map made by hand (bits only) is listed here.
  EdgePoints listed;
  const bool has_list =
      edges.points.row_start.size() == static_cast<std::size_t>(edges.bits.height()) + 1;
  if (!has_list) list_edge_points(edges.bits, edges.dx, edges.dy, listed);
  const EdgePoints& points = has_list ? edges.points : listed;
  // Pixels rounding to a bin in [r0, r1] lie within r1 + 1 of the centre, but the search
  // reaches most of the image: every point of those rows goes through the tests (the counts do
  // not depend on the order), which vector code does faster than finding each row's annulus.
  const double outer = r1 + 1.0;
  const int y0 = std::max(0, static_cast<int>(std::floor(cy - outer)));
  const int y1 = std::min(edges.bits.height() - 1, static_cast<int>(std::ceil(cy + outer)));
  if (y0 > y1) return std::nullopt;
  const auto begin = static_cast<std::size_t>(points.row_start[static_cast<std::size_t>(y0)]);
  const auto end = static_cast<std::size_t>(points.row_start[static_cast<std::size_t>(y1) + 1]);
  const RingBinner binner{cx, cy, r0, r1, r1 + 2};
#if SB_HAVE_AVX2_KERNELS
  if (cpu_has_avx2())
    count_ring_bins_avx2(points, begin, end, binner, hist.data());
  else
#endif
    count_ring_bins(points, begin, end, binner, hist.data());
  double best = 0.0;
  std::optional<double> best_r;
  for (int r = r0; r <= r1; ++r) {
    const int ring = hist[r] + (r > 0 ? hist[r - 1] : 0) + hist[r + 1];
    if (ring < 8) continue;
    const double support = ring / static_cast<double>(r);
    if (support > best) {
      best = support;
      best_r = r;
    }
  }
  return best_r;
}

}  // namespace stereoball::ball_detector
