// refine_circle and score_circle: a circle's outline band on the edge map (the edge pixels of
// an annulus scanned once, tested for band and radial gradient, placed to sub-pixel), fitted
// again in shrinking bands, then scored by the band's angular coverage less the clutter rings'.
// An outline seen obliquely is made round first (OutlineStretch). Apart from the fit
// (circle_fit.cpp) and the coverage (circle_coverage.cpp) it calls: this file finds the band's
// pixels and keeps them for the later, narrower bands.
#include "ball_detector/core/circle_fit.hpp"

#include "ball_detector/core/cpu_dispatch.hpp"
#include "ball_detector/core/fast_math.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

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

}  // namespace

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
