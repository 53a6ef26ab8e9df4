#include "ball_detector/core/circle_fit.hpp"

#include "ball_detector/core/cpu_dispatch.hpp"
#include "ball_detector/core/fast_math.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <memory>
#include <numbers>

namespace stereoball::ball_detector {
namespace {

// The derivative planes as plain pointers: read per gathered point, where cv::Mat::at would
// reload the Mat's fields after every point stored (a stored double may alias them).
struct GradientPlanes {
  const short* dx;
  const short* dy;
  std::ptrdiff_t step;  // in shorts
  int cols, rows;

  explicit GradientPlanes(const EdgeMap& e)
      : dx(e.dx.ptr<short>(0)),
        dy(e.dy.ptr<short>(0)),
        step(static_cast<std::ptrdiff_t>(e.dx.step1())),
        cols(e.dx.cols),
        rows(e.dx.rows) {}
  int l1_at(int x, int y) const {
    const std::ptrdiff_t i = y * step + x;
    return std::abs(dx[i]) + std::abs(dy[i]);
  }
};

// Sub-pixel edge position: parabola through the gradient magnitude at the pixel and its two
// neighbours along the (8-direction quantised) gradient; gx, gy: the derivatives at the pixel.
cv::Point2d subpixel_edge(const GradientPlanes& g, int x, int y, int gx, int gy) {
  if (x < 1 || y < 1 || x >= g.cols - 1 || y >= g.rows - 1) return {double(x), double(y)};
  const int ax = std::abs(gx), ay = std::abs(gy);
  // tan(22.5 deg) ~ 0.4142 ~ 53/128: integer sector test.
  int sx = 0, sy = 0;
  if (ay * 128 <= ax * 53) {
    sx = 1;
  } else if (ax * 128 <= ay * 53) {
    sy = 1;
  } else {
    sx = 1;
    sy = (gx > 0) == (gy > 0) ? 1 : -1;
  }
  const double m0 = ax + ay;  // g.l1_at(x, y)
  const double mm = g.l1_at(x - sx, y - sy);
  const double mp = g.l1_at(x + sx, y + sy);
  const double denom = mm - 2.0 * m0 + mp;
  if (denom >= 0.0) return {double(x), double(y)};
  const double t = std::clamp(0.5 * (mm - mp) / denom, -0.5, 0.5);
  return {x + t * sx, y + t * sy};
}

// static_cast<int>(std::floor(v)) and of std::ceil for |v| < 2^31, without the library call
// the baseline instruction set needs (four per row of an annulus added up).
inline int floor_int(double v) {
  const int t = static_cast<int>(v);
  return t - (v < t);
}

inline int ceil_int(double v) {
  const int t = static_cast<int>(v);
  return t + (v > t);
}

// Calls range(y, x0, x1) for the column ranges [x0, x1] (not clipped to the image) that hold
// the pixels that may lie in the annulus inner <= d <= outer around (cx, cy): per row, the one
// or two ranges the annulus covers (plus a pixel of slack for rounding), rows top down and left
// to right, so the pixels come in raster order as with a box scan.
template <typename F>
[[gnu::always_inline]] inline void for_each_annulus_range(double cx, double cy, double inner,
                                                          double outer, int height, F&& range) {
  const int y0 = std::max(0, static_cast<int>(std::floor(cy - outer)));
  const int y1 = std::min(height - 1, static_cast<int>(std::ceil(cy + outer)));
  for (int y = y0; y <= y1; ++y) {
    const double dy2 = (y - cy) * (y - cy);
    if (dy2 > outer * outer) continue;
    const double half_out = std::sqrt(outer * outer - dy2);
    const int left_out = floor_int(cx - half_out) - 1;
    const int right_out = ceil_int(cx + half_out) + 1;
    const double half_in = dy2 < inner * inner ? std::sqrt(inner * inner - dy2) : 0.0;
    const int left_in = ceil_int(cx - half_in) + 1;
    const int right_in = floor_int(cx + half_in) - 1;
    if (left_in >= right_in) {  // no hole in this row (or too small to skip): one range
      range(y, left_out, right_out);
      continue;
    }
    range(y, left_out, left_in);
    range(y, right_in, right_out);
  }
}

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

cv::Point2d OutlineStretch::to_round(const cv::Point2d& d) const {
  if (identity()) return d;
  return d + axis * ((1.0 / ratio - 1.0) * d.dot(axis));
}

cv::Point2d OutlineStretch::from_round(const cv::Point2d& d) const {
  if (identity()) return d;
  return d + axis * ((ratio - 1.0) * d.dot(axis));
}

cv::Point2d OutlineStretch::gradient_to_round(const cv::Point2d& g) const {
  // Normals transform with the inverse transpose of the (symmetric) compression.
  return from_round(g);
}

OutlineStretch outline_stretch(const EdgeMap& edges, const Circle& c, const RefineParams& params) {
  if (!params.camera) return {};
  stereo::PinholeCamera camera = *params.camera;
  // In a crop's coordinates the whole image starts at frame_px's corner.
  camera.principal_px += cv::Point2d(edges.frame_px.x, edges.frame_px.y);
  const auto view = stereo::sphere_from_outline(camera, {c.x_px, c.y_px}, c.radius_px);
  if (!view || !(view->axis_ratio > 1.0)) return {};
  return {view->major_axis, view->axis_ratio};
}

void gather_circle_points(const EdgeMap& edges, const Circle& c, double band_px,
                          double min_radial_cos, std::vector<cv::Point2d>& out) {
  gather_outline_points(edges, c, OutlineStretch{}, band_px, min_radial_cos, out);
}

namespace {

// The edge pixels of an annulus scan in raster order, waiting for gather_outline_points' band
// and gradient tests: one array per field, so that the tests run four pixels at a time. A
// refinement keeps them for its later, narrower bands: a band inside the annulus scanned finds
// every pixel that can pass its tests among them, in the same order, without a scan.
struct BandCandidates {
  // Arrays of capacity entries, of which the first count are written (not zeroed first: a scan
  // writes a few hundred of them).
  std::unique_ptr<int[]> x, y, keep;  // keep: the tests' scratch
  std::unique_ptr<short[]> gx, gy;
  int capacity = 0;
  int count = 0;
  // The annulus scanned, in the image: centre, inner and outer radius (outer < 0: none yet).
  double cx = 0.0, cy = 0.0, inner = 0.0, outer = -1.0;

  // Room for at least n candidates, keeping the first count.
  void reserve(int n) {
    if (capacity >= n) return;
    const int size = std::max(n, 2 * capacity);
    const auto grow = [&](auto& a) {
      auto bigger = std::make_unique_for_overwrite<std::remove_reference_t<decltype(a[0])>[]>(
          static_cast<std::size_t>(size));
      std::copy(a.get(), a.get() + count, bigger.get());
      a = std::move(bigger);
    };
    grow(x);
    grow(y);
    grow(gx);
    grow(gy);
    keep = std::make_unique_for_overwrite<int[]>(static_cast<std::size_t>(size));
    capacity = size;
  }
  // Whether the annulus inner <= d <= outer around (acx, acy) lies within the one scanned, with
  // a hundredth of a pixel to spare for the rounding of the tests against it.
  bool covers(double acx, double acy, double ainner, double aouter) const {
    const double shift = fast_hypot(acx - cx, acy - cy);
    return outer >= 0.0 && aouter + shift <= outer - 0.01 &&
           (inner <= 0.0 || ainner - shift >= inner + 0.01);
  }
};

// gather_outline_points' tests. Every value the per-point tests read is a member of this local
// copy (the methods are inlined): the points stored are doubles, which may alias the fields of
// the arguments, and the compiler would read them again, and divide again, for every point. The
// arithmetic is that of OutlineStretch's to_round / gradient_to_round, expression by expression.
struct OutlineBand {
  double cx, cy, outer, inner, outer2, inner2, cos2;
  bool identity;
  double ax, ay, to_round, from_round;

  OutlineBand(const Circle& round, const OutlineStretch& stretch, double band_px,
              double min_radial_cos)
      : cx(round.x_px),
        cy(round.y_px),
        outer(round.radius_px + band_px),
        inner(std::max(0.0, round.radius_px - band_px)),
        outer2(outer * outer),
        inner2(inner * inner),
        cos2(min_radial_cos * min_radial_cos),
        identity(stretch.identity()),
        ax(stretch.axis.x),
        ay(stretch.axis.y),
        to_round(1.0 / stretch.ratio - 1.0),
        from_round(stretch.ratio - 1.0) {}

  // The pixel lies in the band and its gradient is radial (after the stretch): 1, else 0.
  [[gnu::always_inline]] int passes(int x, int y, short gx, short gy) const {
    double rx = x - cx, ry = y - cy;
    if (!identity) {
      const double k = to_round * (rx * ax + ry * ay);
      rx = rx + ax * k;
      ry = ry + ay * k;
    }
    const double d2 = rx * rx + ry * ry;
    double g_x = gx, g_y = gy;
    if (!identity) {
      const double k = from_round * (g_x * ax + g_y * ay);
      g_x = g_x + ax * k;
      g_y = g_y + ay * k;
    }
    const double g_dot_r = g_x * rx + g_y * ry;
    const double g2 = g_x * g_x + g_y * g_y;
    return static_cast<int>(!(d2 > outer2) & !(d2 < inner2) &
                            !(g_dot_r * g_dot_r < cos2 * g2 * d2));
  }

  // A passing pixel's sub-pixel position in round coordinates, if that lies in the band too (the
  // band applies to the sub-pixel position, which is what the fit uses).
  [[gnu::always_inline]] std::optional<cv::Point2d> place(const GradientPlanes& planes, int x,
                                                          int y, short gx, short gy) const {
    cv::Point2d p = subpixel_edge(planes, x, y, gx, gy);
    if (!identity) {
      const double sx = p.x - cx, sy = p.y - cy;
      const double k = to_round * (sx * ax + sy * ay);
      p = {cx + (sx + ax * k), cy + (sy + ay * k)};
    }
    const double sd = fast_hypot(p.x - cx, p.y - cy);
    if (sd > outer || sd < inner) return std::nullopt;
    return p;
  }
};

// The candidates [begin, end) that pass band's tests, their indices in order into keep (no
// branch on a pixel: whether one passes is a coin toss to the branch predictor); their count.
int passing_candidates(const OutlineBand& band, const BandCandidates& c, int begin, int end,
                       int* keep) {
  int kept = 0;
  for (int i = begin; i < end; ++i) {
    const auto u = static_cast<std::size_t>(i);
    keep[kept] = i;
    kept += band.passes(c.x[u], c.y[u], c.gx[u], c.gy[u]);
  }
  return kept;
}

#if SB_HAVE_AVX2_KERNELS
// OutlineBand's stretch of four vectors (x, y) along the axis (ax, ay) by factor, in its order:
// k = factor (x ax + y ay), then x + ax k and y + ay k.
[[gnu::always_inline]] SB_TARGET_AVX2 inline void stretch_pd(__m256d& x, __m256d& y, __m256d factor,
                                                             __m256d ax, __m256d ay) {
  const __m256d k =
      _mm256_mul_pd(factor, _mm256_add_pd(_mm256_mul_pd(x, ax), _mm256_mul_pd(y, ay)));
  x = _mm256_add_pd(x, _mm256_mul_pd(ax, k));
  y = _mm256_add_pd(y, _mm256_mul_pd(ay, k));
}

// passing_candidates four pixels at a time: OutlineBand::passes' double operations in its order
// (no fused multiply-add) and its comparisons (negated, so true where it is true with a NaN),
// so the same pixels pass.
SB_TARGET_AVX2 int passing_candidates_avx2(const OutlineBand& band, const BandCandidates& c,
                                           int* keep) {
  const __m256d cx = _mm256_set1_pd(band.cx), cy = _mm256_set1_pd(band.cy);
  const __m256d outer2 = _mm256_set1_pd(band.outer2), inner2 = _mm256_set1_pd(band.inner2);
  const __m256d cos2 = _mm256_set1_pd(band.cos2);
  const __m256d ax = _mm256_set1_pd(band.ax), ay = _mm256_set1_pd(band.ay);
  const __m256d to_round = _mm256_set1_pd(band.to_round);
  const __m256d from_round = _mm256_set1_pd(band.from_round);
  int kept = 0, i = 0;
  for (; i + 4 <= c.count; i += 4) {
    const auto u = static_cast<std::size_t>(i);
    __m256d rx = _mm256_sub_pd(
        _mm256_cvtepi32_pd(_mm_loadu_si128(reinterpret_cast<const __m128i*>(&c.x[u]))), cx);
    __m256d ry = _mm256_sub_pd(
        _mm256_cvtepi32_pd(_mm_loadu_si128(reinterpret_cast<const __m128i*>(&c.y[u]))), cy);
    __m256d gx = _mm256_cvtepi32_pd(
        _mm_cvtepi16_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(&c.gx[u]))));
    __m256d gy = _mm256_cvtepi32_pd(
        _mm_cvtepi16_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(&c.gy[u]))));
    if (!band.identity) stretch_pd(rx, ry, to_round, ax, ay);
    const __m256d d2 = _mm256_add_pd(_mm256_mul_pd(rx, rx), _mm256_mul_pd(ry, ry));
    if (!band.identity) stretch_pd(gx, gy, from_round, ax, ay);
    const __m256d g_dot_r = _mm256_add_pd(_mm256_mul_pd(gx, rx), _mm256_mul_pd(gy, ry));
    const __m256d g2 = _mm256_add_pd(_mm256_mul_pd(gx, gx), _mm256_mul_pd(gy, gy));
    const __m256d in_band = _mm256_and_pd(_mm256_cmp_pd(d2, outer2, _CMP_NGT_UQ),
                                          _mm256_cmp_pd(d2, inner2, _CMP_NLT_UQ));
    const __m256d radial = _mm256_cmp_pd(_mm256_mul_pd(g_dot_r, g_dot_r),
                                         _mm256_mul_pd(_mm256_mul_pd(cos2, g2), d2), _CMP_NLT_UQ);
    const int mask = _mm256_movemask_pd(_mm256_and_pd(in_band, radial));
    for (int j = 0; j < 4; ++j) {
      keep[kept] = i + j;
      kept += (mask >> j) & 1;
    }
  }
  return kept + passing_candidates(band, c, i, c.count, keep + kept);
}
#endif

// The candidates that pass band's tests, placed (OutlineBand::place) and appended to out in
// order.
void place_candidates(const OutlineBand& band, const GradientPlanes& planes_in, BandCandidates& c,
                      std::vector<cv::Point2d>& out) {
  const GradientPlanes planes = planes_in;  // a local copy: its fields stay in registers
  int* const keep = c.keep.get();
#if SB_HAVE_AVX2_KERNELS
  const int kept = cpu_has_avx2() ? passing_candidates_avx2(band, c, keep)
                                  : passing_candidates(band, c, 0, c.count, keep);
#else
  const int kept = passing_candidates(band, c, 0, c.count, keep);
#endif
  for (int k = 0; k < kept; ++k) {
    const auto i = static_cast<std::size_t>(keep[k]);
    if (const auto p = band.place(planes, c.x[i], c.y[i], c.gx[i], c.gy[i])) out.push_back(*p);
  }
}

// Writes the edge pixels that may lie in the annulus inner <= d <= outer around (cx, cy) to c
// (for_each_annulus_range's pixels, in raster order), and the annulus.
void scan_annulus(const EdgeMap& edges, double cx, double cy, double inner, double outer,
                  BandCandidates& c) {
  const GradientPlanes planes(edges);
  c.count = 0;
  int n = 0;  // candidates written
  int* xs = c.x.get();
  int* ys = c.y.get();
  short* gxs = c.gx.get();
  short* gys = c.gy.get();
  const int last_col = edges.bits.width() - 1;
  const auto collect = [&](int y, int x0, int x1) {
    x0 = std::max(0, x0);
    x1 = std::min(last_col, x1);
    if (x1 < x0) return;
    const std::uint64_t* row = edges.bits.row(y);
    const short* gx = planes.dx + y * planes.step;
    const short* gy = planes.dy + y * planes.step;
    const int w0 = x0 >> 6, w1 = x1 >> 6;
    for (int w = w0; w <= w1; ++w) {
      std::uint64_t word = row[w];
      // Only the bits of [x0, x1] in this word.
      if (w == w0) word &= ~std::uint64_t{0} << (x0 & 63);
      if (w == w1) word &= ~std::uint64_t{0} >> (63 - (x1 & 63));
      if (word == 0) continue;
      if (n + 64 > c.capacity) {  // a word's pixels might not fit
        c.count = n;
        c.reserve(n + 1024);
        xs = c.x.get();
        ys = c.y.get();
        gxs = c.gx.get();
        gys = c.gy.get();
      }
      for (; word != 0; word &= word - 1) {
        const int x = (w << 6) + std::countr_zero(word);
        xs[n] = x;
        ys[n] = y;
        gxs[n] = gx[x];
        gys[n] = gy[x];
        ++n;
      }
    }
  };
  for_each_annulus_range(cx, cy, inner, outer, edges.bits.height(), collect);
  c.count = n;
  c.cx = cx;
  c.cy = cy;
  c.inner = inner;
  c.outer = outer;
}

// gather_outline_points, taking the pixels from c when its annulus covers the band's, else
// scanning the band's into c, widened by margin_px on either side for the gathers to come.
void gather_band(const EdgeMap& edges, const Circle& round, const OutlineStretch& stretch,
                 double band_px, double min_radial_cos, double margin_px, BandCandidates& c,
                 std::vector<cv::Point2d>& out) {
  out.clear();
  const OutlineBand band(round, stretch, band_px, min_radial_cos);
  // In the image the band reaches ratio times farther along the major axis.
  const double reach = stretch.ratio * band.outer;
  if (!c.covers(band.cx, band.cy, band.inner, reach))
    scan_annulus(edges, band.cx, band.cy, std::max(0.0, band.inner - margin_px), reach + margin_px,
                 c);
  place_candidates(band, GradientPlanes(edges), c, out);
}

}  // namespace

void gather_outline_points(const EdgeMap& edges, const Circle& round, const OutlineStretch& stretch,
                           double band_px, double min_radial_cos, std::vector<cv::Point2d>& out) {
  // Three stages: the scan writes the edge pixels of the annulus down, the band and gradient
  // tests pick those that pass (about half, in no pattern a branch predictor can learn), and only
  // those get their sub-pixel position. Raster order stays.
  BandCandidates candidates;
  gather_band(edges, round, stretch, band_px, min_radial_cos, 0.0, candidates, out);
}

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

double scoring_band_px(const Circle& c, const RefineParams& params) {
  return std::max(params.band_px, params.band_per_radius * c.radius_px);
}

namespace {

// The circle an outline becomes under its stretch: same centre, the minor semi-axis as radius
// (the mean radius is (a + b) / 2 with a = ratio * b).
Circle round_circle(const Circle& c, const OutlineStretch& stretch) {
  Circle r = c;
  r.radius_px = 2.0 * c.radius_px / (1.0 + stretch.ratio);
  return r;
}

// Back from a circle fitted in the round coordinates of an outline centred at centre.
Circle unround_circle(const Circle& fit, const cv::Point2d& centre, const OutlineStretch& stretch) {
  if (stretch.identity()) return fit;
  const cv::Point2d c = centre + stretch.from_round(cv::Point2d(fit.x_px, fit.y_px) - centre);
  return Circle{c.x, c.y, 0.5 * (1.0 + stretch.ratio) * fit.radius_px, fit.score};
}

// How much wider than its band a refinement scans, px on either side: the fit moves the circle
// by a pixel or so per round, and a later band within the annulus scanned needs no scan.
constexpr double kRescanMarginPx = 2.0;

// Angular coverage of c's outline by the edge points in its scoring band (candidates: the
// pixels of a scan made before, see BandCandidates).
double outline_score(const EdgeMap& edges, const Circle& c, const RefineParams& params,
                     BandCandidates& candidates, std::vector<cv::Point2d>& pts) {
  const OutlineStretch stretch = outline_stretch(edges, c, params);
  const Circle round = round_circle(c, stretch);
  const double band = scoring_band_px(round, params);
  gather_band(edges, round, stretch, band, params.min_radial_cos, kRescanMarginPx, candidates, pts);
  const double coverage =
      angular_coverage_in_frame(round, pts, edges.frame_px, params.min_inside_fraction, stretch);
  // The rings weigh in gradually from clutter_min_radius_px to twice that: a wider band
  // collects more texture by chance, and a patterned ball on textured ground (both rings
  // covered) keeps its mid-sized outline.
  const double weight = params.clutter_min_radius_px > 0.0
                            ? std::min(1.0, round.radius_px / params.clutter_min_radius_px - 1.0)
                            : 1.0;
  // Below the caller's threshold already: the score can only drop (it is dropped either way).
  if (params.clutter_ring_per_radius <= 0.0 || weight <= 0.0 || coverage <= 0.0 ||
      coverage < params.give_up_below)
    return coverage;
  // Texture covers any circle drawn through it about as well as the outline does: subtract
  // the coverage of the same circle grown and shrunk by a few pixels, the cleaner of the two
  // (texture surrounds a chance circle on both sides; a ball's outline has a cleaner side).
  const double step = std::max(2.0, params.clutter_ring_per_radius * round.radius_px);
  if (round.radius_px - step < 2.0) return coverage;  // no inner ring: nothing to compare
  double clutter = 1.0;
  std::vector<cv::Point2d> ring_pts;
  for (double d : {-step, step}) {
    Circle ring = round;
    ring.radius_px += d;
    gather_band(edges, ring, stretch, band, params.min_radial_cos, 0.0, candidates, ring_pts);
    clutter = std::min(clutter, angular_coverage_in_frame(ring, ring_pts, edges.frame_px,
                                                          params.min_inside_fraction, stretch));
  }
  return std::max(0.0, coverage - weight * clutter);
}

}  // namespace

std::optional<Circle> refine_circle(const EdgeMap& edges, const Circle& rough,
                                    const RefineParams& params) {
  Circle c = rough;
  std::vector<cv::Point2d> pts;
  pts.reserve(512);
  // The first round's band is the widest: the later ones, near it, take its pixels.
  BandCandidates candidates;
  for (int it = 0; it < params.iterations; ++it) {
    const OutlineStretch stretch = outline_stretch(edges, c, params);
    const Circle round = round_circle(c, stretch);
    // Shrinking bands: the rough centre from a vote peak may be off by a pixel or two, and a
    // wide band would let texture just inside the rim pull a least-squares fit (a robust fit
    // can start wider: it sees both and keeps to the majority).
    const double band = std::max(scoring_band_px(round, params), params.first_band_px / (1 << it));
    gather_band(edges, round, stretch, band, params.min_radial_cos, kRescanMarginPx, candidates,
                pts);
    // The widest band's coverage bounds the score from above (give_up_below).
    if (it == 0 && params.give_up_below > 0.0 &&
        angular_coverage_in_frame(round, pts, edges.frame_px, params.min_inside_fraction, stretch) <
            params.give_up_below)
      return std::nullopt;
    const auto fit =
        fit_circle(pts, params.robust_fit_floor_px, params.hold_radius ? round.radius_px : 0.0);
    if (!fit) return std::nullopt;
    const Circle next = unround_circle(*fit, {c.x_px, c.y_px}, stretch);
    // A fit that wanders far from its seed has locked onto some other structure.
    if (fast_hypot(next.x_px - rough.x_px, next.y_px - rough.y_px) > 0.5 * rough.radius_px + 3.0)
      return std::nullopt;
    c = next;
  }
  c.score = outline_score(edges, c, params, candidates, pts);
  return c;
}

double score_circle(const EdgeMap& edges, const Circle& c, const RefineParams& params) {
  BandCandidates candidates;
  std::vector<cv::Point2d> pts;
  return outline_score(edges, c, params, candidates, pts);
}

}  // namespace stereoball::ball_detector

namespace stereoball::ball_detector {
namespace {

// An edge point of the annulus around a rough circle, with its unit gradient.
struct OutlinePoint {
  cv::Point2d p;
  cv::Point2d g;
};

// The circle through three points; nullopt when they are (nearly) collinear.
std::optional<Circle> circle_through(const cv::Point2d& a, const cv::Point2d& b,
                                     const cv::Point2d& c) {
  const double d = 2.0 * (a.x * (b.y - c.y) + b.x * (c.y - a.y) + c.x * (a.y - b.y));
  if (std::abs(d) < 1e-6) return std::nullopt;
  const double a2 = a.dot(a), b2 = b.dot(b), c2 = c.dot(c);
  const double x = (a2 * (b.y - c.y) + b2 * (c.y - a.y) + c2 * (a.y - b.y)) / d;
  const double y = (a2 * (c.x - b.x) + b2 * (a.x - c.x) + c2 * (b.x - a.x)) / d;
  return Circle{x, y, std::hypot(a.x - x, a.y - y), 0.0};
}

// Whether q's gradient is radial to circle c within min_cos.
bool radial(const Circle& c, const OutlinePoint& q, double min_cos) {
  const cv::Point2d d(q.p.x - c.x_px, q.p.y - c.y_px);
  const double n = std::hypot(d.x, d.y);
  return n > 0.0 && std::abs(d.dot(q.g)) >= min_cos * n;
}

double band_of(const Circle& c, const OutlineSearchParams& params) {
  return std::max(params.band_px, params.band_per_radius * c.radius_px);
}

// The ball's own colour: per-channel medians over rings at 0.2-0.6 of rough's radius (the
// inside, clear of an outline that is off by a fifth of the radius).
struct SideTest {
  const cv::Mat* image = nullptr;  // CV_8UC3 or CV_8UC1, the edge map's
  cv::Vec3d ball{0, 0, 0};
  double min_contrast = 0.0;

  cv::Vec3d at(const cv::Point2d& p) const {
    const int x = std::clamp(static_cast<int>(std::lround(p.x)), 0, image->cols - 1);
    const int y = std::clamp(static_cast<int>(std::lround(p.y)), 0, image->rows - 1);
    if (image->channels() == 3) {
      const cv::Vec3b v = image->at<cv::Vec3b>(y, x);
      return {double(v[0]), double(v[1]), double(v[2])};
    }
    const double g = image->at<std::uint8_t>(y, x);
    return {g, g, g};
  }
  // Whether the point at p (radial unit u, away from the centre) has the ball's colour inside
  // and something else just outside: an outline, not a seam (ball colour on both sides) or a
  // shading step.
  bool outline_at(const cv::Point2d& p, const cv::Point2d& u, double reach) const {
    if (!image) return true;
    const double in = cv::norm(at(p - reach * u) - ball);
    const double out = cv::norm(at(p + reach * u) - ball);
    return out - in >= min_contrast;
  }
};

SideTest side_test(const EdgeMap& edges, const Circle& rough, double min_contrast) {
  SideTest t;
  const cv::Mat& image = !edges.colour.empty() ? edges.colour : edges.grey;
  if (!(min_contrast > 0.0) || image.empty()) return t;
  t.image = &image;
  t.min_contrast = min_contrast;
  std::array<std::vector<double>, 3> ch;
  for (const double f : {0.2, 0.4, 0.6})
    for (int a = 0; a < 24; ++a) {
      const double ang = 2.0 * std::numbers::pi * (a + 0.5 * f) / 24;
      const cv::Vec3d v = t.at({rough.x_px + f * rough.radius_px * std::cos(ang),
                                rough.y_px + f * rough.radius_px * std::sin(ang)});
      for (int k = 0; k < 3; ++k) ch[k].push_back(v[k]);
    }
  for (int k = 0; k < 3; ++k) {
    auto mid = ch[k].begin() + static_cast<std::ptrdiff_t>(ch[k].size() / 2);
    std::nth_element(ch[k].begin(), mid, ch[k].end());
    t.ball[k] = *mid;
  }
  return t;
}

// The points supporting c (within its band, radial gradient, an outline by their sides).
void supporters(const Circle& c, std::span<const OutlinePoint> pts,
                const OutlineSearchParams& params, const SideTest& sides,
                std::vector<cv::Point2d>& out) {
  out.clear();
  const double band = band_of(c, params);
  const double reach = std::max(2.0, params.side_reach_per_radius * c.radius_px);
  for (const OutlinePoint& q : pts) {
    const cv::Point2d d(q.p.x - c.x_px, q.p.y - c.y_px);
    const double dist = std::hypot(d.x, d.y);
    if (std::abs(dist - c.radius_px) <= band && radial(c, q, params.min_radial_cos) &&
        sides.outline_at(q.p, d / dist, reach))
      out.push_back(q.p);
  }
}

// Edge points of edges within reach of rough's outline (the slacks), with unit gradients.
void annulus_points(const EdgeMap& edges, const Circle& rough, const OutlineSearchParams& params,
                    std::vector<OutlinePoint>& out) {
  out.clear();
  const double r = rough.radius_px;
  const double reach = params.centre_slack * r + params.band_px + params.band_per_radius * r;
  const double lo = std::max(0.0, (1.0 - params.radius_slack) * r - reach);
  const double hi = (1.0 + params.radius_slack) * r + reach;
  const EdgePoints& e = edges.points;
  for (std::size_t i = 0; i < e.x.size(); ++i) {
    const double dx = e.x[i] - rough.x_px, dy = e.y[i] - rough.y_px;
    const double d2 = dx * dx + dy * dy;
    if (d2 < lo * lo || d2 > hi * hi) continue;
    const double gn = std::hypot(static_cast<double>(e.gx[i]), static_cast<double>(e.gy[i]));
    if (gn <= 0.0) continue;
    out.push_back(
        {{static_cast<double>(e.x[i]), static_cast<double>(e.y[i])}, {e.gx[i] / gn, e.gy[i] / gn}});
  }
}

}  // namespace

double outline_coverage(const EdgeMap& edges, const Circle& c, const OutlineSearchParams& params) {
  std::vector<OutlinePoint> pts;
  OutlineSearchParams exact = params;
  exact.radius_slack = exact.centre_slack = 0.0;
  annulus_points(edges, c, exact, pts);
  std::vector<cv::Point2d> support;
  supporters(c, pts, params, side_test(edges, c, params.min_side_contrast), support);
  return angular_coverage_in_frame(c, support, edges.frame_px);
}

std::optional<Circle> robust_outline(const EdgeMap& edges, const Circle& rough,
                                     const OutlineSearchParams& params) {
  if (!(rough.radius_px > 0.0) || !std::isfinite(rough.x_px) || !std::isfinite(rough.y_px))
    return std::nullopt;
  std::vector<OutlinePoint> pts;
  annulus_points(edges, rough, params, pts);
  std::vector<cv::Point2d> support;
  const SideTest sides = side_test(edges, rough, params.min_side_contrast);
  const auto coverage = [&](const Circle& c) {
    supporters(c, pts, params, sides, support);
    return angular_coverage_in_frame(c, support, edges.frame_px);
  };
  Circle kept = rough;
  kept.score = coverage(rough);
  if (pts.size() < 3) return kept;
  const double r = rough.radius_px;
  const double r_lo = (1.0 - params.radius_slack) * r, r_hi = (1.0 + params.radius_slack) * r;
  const double max_shift = params.centre_slack * r;
  // Three points of one outline lie well apart on it: closer ones give an ill-posed circle.
  const double min_apart = 0.5 * r_lo;
  cv::RNG rng(0x5eed);
  const int n = static_cast<int>(pts.size());
  Circle best = kept;
  std::size_t best_support = support.size();
  for (int h = 0; h < params.hypotheses; ++h) {
    const OutlinePoint& a = pts[static_cast<std::size_t>(rng.uniform(0, n))];
    const OutlinePoint& b = pts[static_cast<std::size_t>(rng.uniform(0, n))];
    const OutlinePoint& c = pts[static_cast<std::size_t>(rng.uniform(0, n))];
    if (cv::norm(a.p - b.p) < min_apart || cv::norm(b.p - c.p) < min_apart ||
        cv::norm(a.p - c.p) < min_apart)
      continue;
    const auto circle = circle_through(a.p, b.p, c.p);
    if (!circle || circle->radius_px < r_lo || circle->radius_px > r_hi ||
        std::hypot(circle->x_px - rough.x_px, circle->y_px - rough.y_px) > max_shift)
      continue;
    if (!radial(*circle, a, params.min_radial_cos) || !radial(*circle, b, params.min_radial_cos) ||
        !radial(*circle, c, params.min_radial_cos))
      continue;
    const double cov = coverage(*circle);
    if (cov > best.score || (cov == best.score && support.size() > best_support)) {
      best = *circle;
      best.score = cov;
      best_support = support.size();
    }
  }
  if (best.score < kept.score + params.min_gain) return kept;
  // The supporters' least-squares circle (Tukey weights), twice: it sits on the outline, not
  // on the three sampled points.
  for (int round = 0; round < 2; ++round) {
    supporters(best, pts, params, sides, support);
    const auto fit = fit_circle(support, 0.6);
    if (!fit || fit->radius_px < r_lo || fit->radius_px > r_hi ||
        std::hypot(fit->x_px - rough.x_px, fit->y_px - rough.y_px) > max_shift)
      break;
    const double cov = coverage(*fit);
    if (cov < best.score) break;
    best = *fit;
    best.score = cov;
  }
  return best;
}

}  // namespace stereoball::ball_detector
