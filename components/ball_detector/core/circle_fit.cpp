// fit_circle: the algebraic (Kasa) circle of a set of points, refined by Gauss-Newton steps of
// the geometric fit, least squares or Tukey-weighted (plain and AVX2 sums). Apart from the
// outline bands (circle_refine.cpp): it fits any points, wherever they come from.
#include "ball_detector/core/circle_fit.hpp"

#include "ball_detector/core/cpu_dispatch.hpp"
#include "ball_detector/core/fast_math.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace stereoball::ball_detector {
namespace {

// Tukey's biweight: 1 at the circle, falling to 0 at |res| = cut.
double tukey_weight(double res, double cut) {
  const double u = res / cut;
  if (u * u >= 1.0) return 0.0;
  const double v = 1.0 - u * u;
  return v * v;
}

// 4.7 robust sigmas (1.4826 x the median absolute residual), at least floor_px: the cut that
// keeps 95 % efficiency on clean Gaussian residuals. dist: each point's distance from the centre,
// for the Gauss-Newton step that follows (the same expression there).
double robust_cut_px(std::span<const cv::Point2d> points, const cv::Point2d& mean, double cx,
                     double cy, double r, double floor_px, std::vector<double>& residuals,
                     std::vector<double>& dist) {
  constexpr double kSigmas = 4.685 * 1.4826;
  const std::size_t n = points.size(), m = n / 2;
  residuals.resize(n);
  dist.resize(n);
  // The cut is clamped to [floor_px, 2 floor_px]: counted on either side of the clamp, the
  // median often needs no selection (kSigmas x residual grows with the residual, so the
  // residuals on one side are the smallest or the largest ones).
  std::size_t below = 0, above = 0, nan = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const cv::Point2d& p = points[i];
    dist[i] = fast_hypot(p.x - mean.x - cx, p.y - mean.y - cy);
    const double res = std::abs(dist[i] - r);
    residuals[i] = res;
    below += kSigmas * res <= floor_px;
    above += kSigmas * res >= 2.0 * floor_px;
    nan += res != res;
  }
  if (nan == 0 && below > m) return floor_px;             // the median's cut is at most the floor
  if (nan == 0 && above >= n - m) return 2.0 * floor_px;  // ... at least twice the floor
  const auto mid = residuals.begin() + static_cast<std::ptrdiff_t>(m);
  std::nth_element(residuals.begin(), mid, residuals.end());
  return std::min(std::max(floor_px, kSigmas * *mid), 2.0 * floor_px);
}

// fit_circle's start: the algebraic (Kasa) circle x^2 + y^2 + D x + E y + F = 0 of points in
// coordinates centred on mean (better conditioned): its centre and squared radius there. The
// normal matrix of the rows (x, y, 1) is symmetric: each distinct sum once.
std::optional<cv::Vec3d> kasa_circle(std::span<const cv::Point2d> points, const cv::Point2d& mean) {
  double sxx = 0, sxy = 0, sx = 0, syy = 0, sy = 0, n = 0, bx = 0, by = 0, b1 = 0;
  for (const auto& p : points) {
    const double x = p.x - mean.x, y = p.y - mean.y;
    const double rhs = -(x * x + y * y);
    bx += x * rhs;
    by += y * rhs;
    b1 += rhs;
    sxx += x * x;
    sxy += x * y;
    sx += x;
    syy += y * y;
    sy += y;
    n += 1.0;
  }
  const auto sol = solve_3x3(cv::Matx33d(sxx, sxy, sx, sxy, syy, sy, sx, sy, n), {bx, by, b1});
  if (!sol) return std::nullopt;
  const double cx = -(*sol)[0] / 2.0, cy = -(*sol)[1] / 2.0;
  return cv::Vec3d(cx, cy, cx * cx + cy * cy - (*sol)[2]);
}

// The sums of a Gauss-Newton step's normal equations (gauss_newton_step): with j = (-x / d,
// -y / d, -1) and weight w, s_ab sums (w j_a) j_b and t_a sums (w j_a) res. The products with
// j_2 = -1 are exact negations, so the third row and column are the third column's sums.
struct NormalSums {
  double s00 = 0, s01 = 0, s10 = 0, s11 = 0, s02 = 0, s12 = 0, s22 = 0;
  double t0 = 0, t1 = 0, t2 = 0;
};

// What a Gauss-Newton step reads: the points (centred on mean), the circle (cx, cy, r), the
// Tukey cut (0 = least squares) and the points' distances from the centre when already
// measured (robust_cut_px), else empty.
struct StepInput {
  std::span<const cv::Point2d> points;
  cv::Point2d mean;
  double cx, cy, r, cut;
  std::span<const double> dist;
};

// Adds points [begin, end) of in to s, in order.
void add_normal_sums(const StepInput& in, std::size_t begin, NormalSums& s) {
  for (std::size_t i = begin; i < in.points.size(); ++i) {
    const cv::Point2d& p = in.points[i];
    const double x = p.x - in.mean.x - in.cx, y = p.y - in.mean.y - in.cy;
    const double d = in.dist.empty() ? fast_hypot(x, y) : in.dist[i];
    if (d < 1e-9) continue;
    const double jx = -x / d, jy = -y / d;
    const double res = d - in.r;
    const double w = in.cut > 0.0 ? tukey_weight(res, in.cut) : 1.0;
    if (w <= 0.0) continue;
    const double wx = w * jx, wy = w * jy;
    s.t0 += wx * res;
    s.t1 += wy * res;
    s.t2 -= w * res;
    s.s00 += wx * jx;
    s.s01 += wx * jy;
    s.s02 -= wx;
    s.s10 += wy * jx;
    s.s11 += wy * jy;
    s.s12 -= wy;
    s.s22 += w;
  }
}

#if SB_HAVE_AVX2_KERNELS
// Four vectors of four as four vectors of the lanes: r_k = (a_k, b_k, c_k, d_k).
SB_TARGET_AVX2 inline void transpose4(__m256d& a, __m256d& b, __m256d& c, __m256d& d) {
  const __m256d ab_even = _mm256_unpacklo_pd(a, b), ab_odd = _mm256_unpackhi_pd(a, b);
  const __m256d cd_even = _mm256_unpacklo_pd(c, d), cd_odd = _mm256_unpackhi_pd(c, d);
  a = _mm256_permute2f128_pd(ab_even, cd_even, 0x20);
  b = _mm256_permute2f128_pd(ab_odd, cd_odd, 0x20);
  c = _mm256_permute2f128_pd(ab_even, cd_even, 0x31);
  d = _mm256_permute2f128_pd(ab_odd, cd_odd, 0x31);
}

// v in the lanes of kept, -0.0 in the others.
SB_TARGET_AVX2 inline __m256d kept_or_neg_zero(__m256d kept, __m256d v) {
  return _mm256_blendv_pd(_mm256_set1_pd(-0.0), v, kept);
}

// add_normal_sums from the first point, four points at a time: each point's terms as vectors
// (add_normal_sums' double operations in its order, no fused multiply-add), then added to the
// sums point by point in order, each sum a lane (a subtracted term is added negated, the same
// bits). A point add_normal_sums skips adds -0.0, which leaves any sum unchanged (-0.0 too).
SB_TARGET_AVX2 void add_normal_sums_avx2(const StepInput& in, NormalSums& s) {
  const __m256d mx = _mm256_set1_pd(in.mean.x), my = _mm256_set1_pd(in.mean.y);
  const __m256d cx = _mm256_set1_pd(in.cx), cy = _mm256_set1_pd(in.cy);
  const __m256d r = _mm256_set1_pd(in.r), cut = _mm256_set1_pd(in.cut);
  const __m256d sign = _mm256_set1_pd(-0.0), one = _mm256_set1_pd(1.0);
  const __m256d zero = _mm256_setzero_pd(), tiny = _mm256_set1_pd(1e-9);
  const bool robust = in.cut > 0.0;
  // Lanes: (s00, s01, s10, s11), (s02, s12, s22, t0), (t1, t2, unused, unused).
  __m256d acc_a = _mm256_setr_pd(s.s00, s.s01, s.s10, s.s11);
  __m256d acc_b = _mm256_setr_pd(s.s02, s.s12, s.s22, s.t0);
  __m256d acc_c = _mm256_setr_pd(s.t1, s.t2, 0.0, 0.0);
  const double* xy = reinterpret_cast<const double*>(in.points.data());
  std::size_t i = 0;
  for (; i + 4 <= in.points.size(); i += 4) {
    // (x0, y0, x1, y1), (x2, y2, x3, y3) as (x0..x3), (y0..y3).
    const __m256d p01 = _mm256_loadu_pd(xy + 2 * i), p23 = _mm256_loadu_pd(xy + 2 * i + 4);
    const __m256d px = _mm256_permute4x64_pd(_mm256_unpacklo_pd(p01, p23), 0xD8);
    const __m256d py = _mm256_permute4x64_pd(_mm256_unpackhi_pd(p01, p23), 0xD8);
    const __m256d x = _mm256_sub_pd(_mm256_sub_pd(px, mx), cx);
    const __m256d y = _mm256_sub_pd(_mm256_sub_pd(py, my), cy);
    const __m256d d = in.dist.empty()
                          ? _mm256_sqrt_pd(_mm256_add_pd(_mm256_mul_pd(x, x), _mm256_mul_pd(y, y)))
                          : _mm256_loadu_pd(in.dist.data() + i);
    const __m256d jx = _mm256_div_pd(_mm256_xor_pd(x, sign), d);
    const __m256d jy = _mm256_div_pd(_mm256_xor_pd(y, sign), d);
    const __m256d res = _mm256_sub_pd(d, r);
    __m256d w = one;
    if (robust) {  // tukey_weight
      const __m256d u = _mm256_div_pd(res, cut);
      const __m256d u2 = _mm256_mul_pd(u, u);
      const __m256d v = _mm256_sub_pd(one, u2);
      w = _mm256_blendv_pd(_mm256_mul_pd(v, v), zero, _mm256_cmp_pd(u2, one, _CMP_GE_OQ));
    }
    const __m256d kept =
        _mm256_and_pd(_mm256_cmp_pd(d, tiny, _CMP_NLT_UQ), _mm256_cmp_pd(w, zero, _CMP_NLE_UQ));
    const __m256d wx = _mm256_mul_pd(w, jx), wy = _mm256_mul_pd(w, jy);
    __m256d a0 = kept_or_neg_zero(kept, _mm256_mul_pd(wx, jx)),
            a1 = kept_or_neg_zero(kept, _mm256_mul_pd(wx, jy));
    __m256d a2 = kept_or_neg_zero(kept, _mm256_mul_pd(wy, jx)),
            a3 = kept_or_neg_zero(kept, _mm256_mul_pd(wy, jy));
    __m256d b0 = kept_or_neg_zero(kept, _mm256_xor_pd(wx, sign)),
            b1 = kept_or_neg_zero(kept, _mm256_xor_pd(wy, sign));
    __m256d b2 = kept_or_neg_zero(kept, w), b3 = kept_or_neg_zero(kept, _mm256_mul_pd(wx, res));
    __m256d c0 = kept_or_neg_zero(kept, _mm256_mul_pd(wy, res)),
            c1 = kept_or_neg_zero(kept, _mm256_xor_pd(_mm256_mul_pd(w, res), sign));
    __m256d c2 = sign, c3 = sign;
    transpose4(a0, a1, a2, a3);
    transpose4(b0, b1, b2, b3);
    transpose4(c0, c1, c2, c3);
    acc_a = _mm256_add_pd(_mm256_add_pd(_mm256_add_pd(_mm256_add_pd(acc_a, a0), a1), a2), a3);
    acc_b = _mm256_add_pd(_mm256_add_pd(_mm256_add_pd(_mm256_add_pd(acc_b, b0), b1), b2), b3);
    acc_c = _mm256_add_pd(_mm256_add_pd(_mm256_add_pd(_mm256_add_pd(acc_c, c0), c1), c2), c3);
  }
  alignas(32) double a[4], b[4], c[4];
  _mm256_store_pd(a, acc_a);
  _mm256_store_pd(b, acc_b);
  _mm256_store_pd(c, acc_c);
  s = NormalSums{a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3], c[0], c[1]};
  add_normal_sums(in, i, s);
}
#endif

// One Gauss-Newton step of the geometric fit of in's circle: the change of (cx, cy, r); each
// point weighted by Tukey's biweight when in.cut > 0; the radius held when hold_radius. nullopt
// when the normal equations cannot be solved.
std::optional<cv::Vec3d> gauss_newton_step(const StepInput& in, bool hold_radius) {
  NormalSums s;
#if SB_HAVE_AVX2_KERNELS
  if (cpu_has_avx2())
    add_normal_sums_avx2(in, s);
  else
#endif
    add_normal_sums(in, 0, s);
  if (hold_radius) {  // the centre only: the upper-left 2 x 2 block
    const auto d2 = solve_2x2(cv::Matx22d(s.s00, s.s01, s.s10, s.s11), cv::Vec2d(-s.t0, -s.t1));
    if (!d2) return std::nullopt;
    return cv::Vec3d((*d2)[0], (*d2)[1], 0.0);
  }
  return solve_3x3(cv::Matx33d(s.s00, s.s01, s.s02, s.s10, s.s11, s.s12, s.s02, s.s12, s.s22),
                   cv::Vec3d(-s.t0, -s.t1, -s.t2));
}

}  // namespace

std::optional<Circle> fit_circle(std::span<const cv::Point2d> points, double robust_floor_px,
                                 double fixed_radius_px) {
  const int n = static_cast<int>(points.size());
  if (n < 3) return std::nullopt;
  cv::Point2d mean(0, 0);
  for (const auto& p : points) mean += p;
  mean *= 1.0 / n;
  const auto kasa = kasa_circle(points, mean);
  if (!kasa) return std::nullopt;
  double cx = (*kasa)[0], cy = (*kasa)[1];
  const double r2 = (*kasa)[2];
  if (!(r2 > 0.0)) return std::nullopt;
  const bool hold_radius = fixed_radius_px > 0.0;
  double r = hold_radius ? fixed_radius_px : std::sqrt(r2);
  // Geometric refinement: Kasa is biased on short arcs and noisy points.
  const int rounds = robust_floor_px > 0.0 ? 8 : 5;  // reweighting converges more slowly
  std::vector<double> residuals, dist;
  for (int it = 0; it < rounds; ++it) {
    const double cut = robust_floor_px > 0.0 ? robust_cut_px(points, mean, cx, cy, r,
                                                             robust_floor_px, residuals, dist)
                                             : 0.0;
    const auto delta = gauss_newton_step({points, mean, cx, cy, r, cut, dist}, hold_radius);
    if (!delta) break;
    cx += (*delta)[0];
    cy += (*delta)[1];
    r += (*delta)[2];
    if (std::abs((*delta)[0]) + std::abs((*delta)[1]) + std::abs((*delta)[2]) < 1e-4) break;
  }
  if (!(r > 0.0) || !std::isfinite(cx) || !std::isfinite(cy)) return std::nullopt;
  return Circle{cx + mean.x, cy + mean.y, r, 0.0};
}

}  // namespace stereoball::ball_detector
