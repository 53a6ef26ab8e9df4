// From accumulator peaks to circles: the voters whose lines pass a peak (plain and AVX2 tests),
// the seed radius from their distances, the seed refined (with a second seed, a rescue and a
// nested circle of another size), then the best separated circles kept and polished. Apart from
// the voting (p2p_voting.cpp): this stage reads the voters and the edge map, not the windows.
#include "ball_detector/core/p2p_detector.hpp"

#include "ball_detector/core/cpu_dispatch.hpp"
#include "ball_detector/core/fast_math.hpp"
#include "ball_detector/core/p2p_detector_internal.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace stereoball::ball_detector {

using p2p_detail::best_separated;
using p2p_detail::polish_refine_params;

namespace {

constexpr double kRingSeedBelowScore = 0.8;
// nested_circle: the voters at another distance must be this many, and this share of all.
constexpr double kNestedMinVoters = 12.0;
constexpr double kNestedMinShare = 0.25;

double median_of(std::vector<double>& v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// CandidateOptions::voter_mode_radius: the 3-px ring of distances holding the most voters per
// pixel of radius (circumference), then the mean distance of the voters in it.
double densest_radius(const std::vector<double>& radii, double min_r, double max_r) {
  const int r0 = std::max(1, static_cast<int>(std::floor(min_r)));
  const int r1 = std::max(r0, static_cast<int>(std::ceil(max_r)));
  std::vector<int> hist(static_cast<std::size_t>(r1 + 2), 0);
  for (double r : radii)
    ++hist[static_cast<std::size_t>(std::clamp(static_cast<int>(r + 0.5), 0, r1 + 1))];
  int best_bin = -1;
  double best = 0.0;
  for (int b = r0; b <= r1; ++b) {
    const double ring = hist[b - 1] + hist[b] + hist[b + 1];
    if (ring >= 3 && ring / b > best) {
      best = ring / b;
      best_bin = b;
    }
  }
  if (best_bin < 0) {
    std::vector<double> copy = radii;
    return median_of(copy);
  }
  double sum = 0.0;
  int n = 0;
  for (double r : radii)
    if (std::abs(r - best_bin) <= 1.5) {
      sum += r;
      ++n;
    }
  return sum / n;
}

// Sectors of the directions from a peak to its voters (CandidateOptions::min_voted_coverage).
constexpr int kVoterSectors = 16;
int voter_sector(double px, double py) {
  const double a = std::atan2(py, px) + std::numbers::pi;  // [0, 2 pi]
  return std::min(kVoterSectors - 1,
                  static_cast<int>(a * (kVoterSectors / (2.0 * std::numbers::pi))));
}

// Radii that differ by less than PixelToPixelParams::kSameCircleRadiusRatio of the larger.
bool same_size(double a_px, double b_px) {
  return std::abs(a_px - b_px) < PixelToPixelParams::kSameCircleRadiusRatio * std::max(a_px, b_px);
}

// Two circles are one when their centres are closer than min_sep and they are of one size.
bool far_from_all(const std::vector<Circle>& kept, const Circle& c, double min_sep) {
  return std::none_of(kept.begin(), kept.end(), [&](const Circle& k) {
    return fast_hypot(k.x_px - c.x_px, k.y_px - c.y_px) < min_sep &&
           same_size(k.radius_px, c.radius_px);
  });
}

}  // namespace

VoterRows::VoterRows(const std::vector<Voter>& voters) {
  const size_t n = voters.size();
  prefix_max_.resize(n);
  suffix_min_.resize(n);
  size_t begin = 0;
  for (size_t i = 0; i < n; ++i) {
    // A big drop in y starts a new run (the next k's raster pass).
    if (i > begin && voters[i].y < prefix_max_[i - 1] - kNewRunDropPx) {
      runs_.push_back({begin, i});
      begin = i;
    }
    prefix_max_[i] = i > begin ? std::max(prefix_max_[i - 1], voters[i].y) : voters[i].y;
  }
  if (n > begin) runs_.push_back({begin, n});
  for (const auto& run : runs_)
    for (size_t i = run.end; i-- > run.begin;)
      suffix_min_[i] = i + 1 < run.end ? std::min(suffix_min_[i + 1], voters[i].y) : voters[i].y;
}

namespace {

void sort_by_score(std::vector<Circle>& circles) {
  std::stable_sort(circles.begin(), circles.end(),
                   [](const Circle& a, const Circle& b) { return a.score > b.score; });
}

// PixelToPixelParams::polish: each circle refined again, robustly from a wider band; kept as it
// was when that fails (too few points, wandered off) or scores below min_score, then the list
// re-sorted by score. The robust fit's score is taken even when lower: the least-squares circle
// pulled between outline and texture can cover more of both than the outline alone.
void polish_circles(const EdgeMap& edges, const RefineParams& refine, double min_score,
                    std::vector<Circle>& circles) {
  const RefineParams robust = polish_refine_params(refine);
  for (Circle& c : circles) {
    const auto polished = refine_circle(edges, c, robust);
    if (polished && polished->score >= min_score) c = *polished;
  }
  sort_by_score(circles);
}

}  // namespace

// The best circles first, none within min_separation_px of a better one, at most max_circles.
std::vector<Circle> p2p_detail::best_separated(std::vector<Circle> found, double min_separation_px,
                                               int max_circles) {
  sort_by_score(found);
  std::vector<Circle> kept;
  for (const auto& c : found) {
    if (static_cast<int>(kept.size()) >= max_circles) break;
    // Two peaks of one ball (e.g. its seam) refine onto the same circle: keep the better. A
    // circle of another size around about the same centre is kept beside it: a striped ball's
    // stripe round its cap is a full circle too, often better contrasted than the outline,
    // and only the outline has the ball's size.
    if (far_from_all(kept, c, std::max(min_separation_px, 1.0))) kept.push_back(c);
  }
  return kept;
}

std::vector<Circle> circles_from_votes(const EdgeMap& edges, const std::vector<Voter>& voters,
                                       const std::vector<Peak>& peaks,
                                       const CandidateOptions& options) {
  const VoterRows rows(voters);
  std::vector<Circle> found;
  for (const auto& peak : peaks) {
    const PeakCircles circles = circle_from_peak(edges, voters, rows, peak, options);
    found.insert(found.end(), circles.begin(), circles.end());
  }
  return select_circles(edges, std::move(found), options);
}

namespace {

std::optional<Circle> refine_or_score(const EdgeMap& edges, const Circle& seed,
                                      const CandidateOptions& options) {
  if (options.refine) return refine_circle(edges, seed, options.refine_params);
  Circle unrefined = seed;
  unrefined.score = score_circle(edges, seed, options.refine_params);
  return unrefined;
}

bool acceptable(const std::optional<Circle>& c, const CandidateOptions& options) {
  return c && c->score >= options.min_score && c->radius_px >= options.min_radius_px &&
         c->radius_px <= options.max_radius_px;
}

// A striped ball's stripe round its cap is a full circle a few pixels off its outline's centre:
// the two peaks merge into one, whose voters lie at two distances. The distance most voters
// away from the circle found share (another size: kSameCircleRadiusRatio or more) seeds a
// second circle. Only around a circle found: texture peaks have voters at every distance.
std::optional<Circle> nested_circle(const EdgeMap& edges, const Peak& peak,
                                    const std::vector<double>& radii, const Circle& found,
                                    const CandidateOptions& options) {
  std::vector<double> other;
  for (const double r : radii)
    if (!same_size(r, found.radius_px)) other.push_back(r);
  if (static_cast<double>(other.size()) <
      std::max(kNestedMinVoters, kNestedMinShare * radii.size()))
    return std::nullopt;
  const double r = densest_radius(other, options.min_radius_px, options.max_radius_px);
  const auto nested = refine_or_score(
      edges, Circle{static_cast<double>(peak.x), static_cast<double>(peak.y), r, 0.0}, options);
  if (!acceptable(nested, options) || same_size(nested->radius_px, found.radius_px))
    return std::nullopt;
  return nested;
}

// circle_from_peak's first stage: the voters whose lines pass the peak within the radius range,
// their distances to it and the sectors around it they lie in. passing: one slot per voter.
struct PeakVoters {
  std::vector<double> radii;
  std::uint32_t sectors = 0;  // bit s: a voter lies in sector s around the peak
};

// The tests of a voter's line against a peak (px, py: peak minus voter, t: distance along the
// line, cross: distance across it), one function for the plain and the vector loops alike.
struct LineTest {
  // The peak's integer coordinates as float: peak minus voter is a float difference (an int
  // minus a float), widened to double after.
  float peak_x, peak_y;
  double tolerance_px;
  // Through: t in [t_min, t_max]. Support: t > 0 and the voter's distance within ring_slack of
  // ring_r.
  double t_min, t_max;
  double ring_r, ring_slack;
};

template <bool Support>
std::size_t pass_lines(const Voter* voters, std::size_t begin, std::size_t end, const LineTest& lt,
                       std::uint32_t* passing, std::size_t n) {
  for (std::size_t i = begin; i < end; ++i) {
    const Voter& v = voters[i];
    const double px = lt.peak_x - v.x, py = lt.peak_y - v.y;
    const double t = px * v.ux + py * v.uy;
    const bool on_line = !(std::abs(px * v.uy - py * v.ux) > lt.tolerance_px);
    bool pass;
    if constexpr (Support)
      pass = on_line & !(t <= 0.0) &
             !(std::abs(std::sqrt(px * px + py * py) - lt.ring_r) > lt.ring_slack);
    else
      pass = !(t < lt.t_min) & !(t > lt.t_max) & on_line;
    passing[n] = static_cast<std::uint32_t>(i);
    n += static_cast<std::size_t>(pass);
  }
  return n;
}

#if SB_HAVE_AVX2_KERNELS
// pass_lines four voters at a time: the same float and double operations in the same order (no
// fused multiply-add; square roots are exact in both), so the same voters pass.
template <bool Support>
SB_TARGET_AVX2 std::size_t pass_lines_avx2(const Voter* voters, std::size_t begin, std::size_t end,
                                           const LineTest& lt, std::uint32_t* passing,
                                           std::size_t n) {
  const __m128 peak_x = _mm_set1_ps(lt.peak_x), peak_y = _mm_set1_ps(lt.peak_y);
  const __m256d tolerance = _mm256_set1_pd(lt.tolerance_px), sign = _mm256_set1_pd(-0.0);
  const __m256d t_min = _mm256_set1_pd(lt.t_min), t_max = _mm256_set1_pd(lt.t_max);
  const __m256d zero = _mm256_setzero_pd();
  const __m256d ring_r = _mm256_set1_pd(lt.ring_r), ring_slack = _mm256_set1_pd(lt.ring_slack);
  static_assert(sizeof(Voter) == 4 * sizeof(float));
  std::size_t i = begin;
  for (; i + 4 <= end; i += 4) {
    // Four voters (x, y, ux, uy) transposed into four vectors of one field each.
    __m128 a = _mm_loadu_ps(&voters[i].x), b = _mm_loadu_ps(&voters[i + 1].x);
    __m128 c = _mm_loadu_ps(&voters[i + 2].x), d = _mm_loadu_ps(&voters[i + 3].x);
    _MM_TRANSPOSE4_PS(a, b, c, d);
    const __m256d px = _mm256_cvtps_pd(_mm_sub_ps(peak_x, a));
    const __m256d py = _mm256_cvtps_pd(_mm_sub_ps(peak_y, b));
    const __m256d ux = _mm256_cvtps_pd(c), uy = _mm256_cvtps_pd(d);
    const __m256d t = _mm256_add_pd(_mm256_mul_pd(px, ux), _mm256_mul_pd(py, uy));
    const __m256d cross = _mm256_sub_pd(_mm256_mul_pd(px, uy), _mm256_mul_pd(py, ux));
    __m256d pass = _mm256_cmp_pd(_mm256_andnot_pd(sign, cross), tolerance, _CMP_NGT_UQ);
    if constexpr (Support) {
      const __m256d dist =
          _mm256_sqrt_pd(_mm256_add_pd(_mm256_mul_pd(px, px), _mm256_mul_pd(py, py)));
      const __m256d off = _mm256_andnot_pd(sign, _mm256_sub_pd(dist, ring_r));
      pass = _mm256_and_pd(pass, _mm256_cmp_pd(t, zero, _CMP_NLE_UQ));
      pass = _mm256_and_pd(pass, _mm256_cmp_pd(off, ring_slack, _CMP_NGT_UQ));
    } else {
      pass = _mm256_and_pd(pass, _mm256_cmp_pd(t, t_min, _CMP_NLT_UQ));
      pass = _mm256_and_pd(pass, _mm256_cmp_pd(t, t_max, _CMP_NGT_UQ));
    }
    const auto mask = static_cast<unsigned>(_mm256_movemask_pd(pass));
    for (unsigned lane = 0; lane < 4; ++lane) {
      passing[n] = static_cast<std::uint32_t>(i + lane);
      n += (mask >> lane) & 1u;
    }
  }
  return pass_lines<Support>(voters, i, end, lt, passing, n);
}
#endif

// The voters of rows' ranges around a peak that pass LineTest, their indices into passing (one
// slot per voter), in the voters' order; returns how many. Whether a voter's line passes the
// peak is a coin toss to the branch predictor: the tests write the voters that pass down
// without a branch.
template <bool Support>
std::size_t passing_voters(const std::vector<Voter>& voters, const VoterRows& rows, double y_lo,
                           double y_hi, const LineTest& lt, std::uint32_t* passing) {
  std::size_t n = 0;
  rows.for_each_range(y_lo, y_hi, [&](std::size_t begin, std::size_t end) {
#if SB_HAVE_AVX2_KERNELS
    if (cpu_has_avx2()) {
      n = pass_lines_avx2<Support>(voters.data(), begin, end, lt, passing, n);
      return;
    }
#endif
    n = pass_lines<Support>(voters.data(), begin, end, lt, passing, n);
  });
  return n;
}

PeakVoters voters_through_peak(const std::vector<Voter>& voters, const VoterRows& rows,
                               const Peak& peak, const CandidateOptions& options,
                               std::uint32_t* passing) {
  PeakVoters out;
  // A voter passing the tests below is at most this far from the peak (t <= max radius and
  // the line within tolerance), plus a pixel for float rounding.
  const double reach_px = options.max_radius_px + options.line_tolerance_px + 1.0;
  const LineTest lt{static_cast<float>(peak.x),
                    static_cast<float>(peak.y),
                    options.line_tolerance_px,
                    options.min_radius_px,
                    options.max_radius_px,
                    0.0,
                    0.0};
  const std::size_t n =
      passing_voters<false>(voters, rows, peak.y - reach_px, peak.y + reach_px, lt, passing);
  out.radii.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Voter& v = voters[passing[i]];
    const double px = peak.x - v.x, py = peak.y - v.y;
    out.radii.push_back(std::sqrt(px * px + py * py));
    if (options.min_voted_coverage > 0.0) out.sectors |= 1u << voter_sector(px, py);
  }
  return out;
}

// The positions of the voters about r0 from the peak whose lines pass it (they are edge points
// on the circle): they seed the fit.
std::vector<cv::Point2d> support_points(const std::vector<Voter>& voters, const VoterRows& rows,
                                        const Peak& peak, const CandidateOptions& options,
                                        double r0, std::uint32_t* passing) {
  const double support_reach_px = 1.2 * r0 + 2.0;
  const LineTest lt{static_cast<float>(peak.x),
                    static_cast<float>(peak.y),
                    options.line_tolerance_px,
                    0.0,
                    0.0,
                    r0,
                    0.2 * r0 + 1.0};
  const std::size_t n = passing_voters<true>(voters, rows, peak.y - support_reach_px,
                                             peak.y + support_reach_px, lt, passing);
  std::vector<cv::Point2d> support;
  support.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Voter& v = voters[passing[i]];
    support.emplace_back(v.x, v.y);
  }
  return support;
}

// The peak at radius r0, or the circle through the support points when it stays near the peak.
Circle first_seed(const Peak& peak, double r0, std::span<const cv::Point2d> support) {
  Circle seed{static_cast<double>(peak.x), static_cast<double>(peak.y), r0, 0.0};
  if (const auto fit = fit_circle(support);
      fit && fast_hypot(fit->x_px - seed.x_px, fit->y_px - seed.y_px) < 0.3 * r0 + 2.0)
    seed = *fit;
  return seed;
}

// The seed refined; when that is weak, a second seed at the peak (median_r: the voters' median
// distance, used with voter_mode_radius) refined too, the better kept.
std::optional<Circle> refine_from_seeds(const EdgeMap& edges, const Peak& peak, const Circle& seed,
                                        double median_r, const CandidateOptions& options) {
  auto refine_seed = [&](const Circle& s) { return refine_or_score(edges, s, options); };
  std::optional<Circle> c = refine_seed(seed);
  // Second seed only when the first is weak: the ring of edge points around the peak.
  // Voters from texture inside a ball can drag the voters' median radius; the ring cannot.
  if (options.voter_mode_radius && (!c || c->score < kRingSeedBelowScore) &&
      std::abs(median_r - seed.radius_px) > 1.5) {
    // The densest ring may be round texture inside a ball: its outline is then the median.
    const auto alt = refine_seed(
        Circle{static_cast<double>(peak.x), static_cast<double>(peak.y), median_r, 0.0});
    if (alt && (!c || alt->score > c->score)) c = alt;
  }
  if (!options.voter_mode_radius && (!c || c->score < kRingSeedBelowScore)) {
    if (const auto ring_r =
            estimate_radius(edges, peak.x, peak.y, options.min_radius_px, options.max_radius_px);
        ring_r && std::abs(*ring_r - seed.radius_px) > 1.5) {
      const auto alt = refine_seed(
          Circle{static_cast<double>(peak.x), static_cast<double>(peak.y), *ring_r, 0.0});
      if (alt && (!c || alt->score > c->score)) c = alt;
    }
  }
  return c;
}

// PixelToPixelParams::rescue_weak_from: a weak circle may be an outline the fit was pulled off.
// Only a refit that can still reach min_score is worth its later rounds (give_up_below).
void rescue_weak(const EdgeMap& edges, const CandidateOptions& options, std::optional<Circle>& c) {
  if (!(options.refine && c && c->score >= options.rescue_weak_from &&
        c->score < options.min_score))
    return;
  RefineParams robust = polish_refine_params(options.refine_params);
  robust.give_up_below = std::max(robust.give_up_below, options.min_score);
  if (const auto refit = refine_circle(edges, *c, robust); refit && refit->score > c->score)
    c = refit;
}

}  // namespace

PeakCircles circle_from_peak(const EdgeMap& edges, const std::vector<Voter>& voters,
                             const VoterRows& rows, const Peak& peak,
                             const CandidateOptions& options) {
  // One slot per voter, kept across calls (grown only: no clearing per peak).
  thread_local std::vector<std::uint32_t> passing_store;
  if (passing_store.size() < voters.size()) passing_store.resize(voters.size());
  std::uint32_t* const passing = passing_store.data();
  PeakVoters through = voters_through_peak(voters, rows, peak, options, passing);
  std::vector<double>& radii = through.radii;
  if (radii.size() < 3) return {};
  // A ball's outline votes from all sides, texture from one: judged on every voter of the
  // peak (not only those at the median distance, which other lines passing by can skew).
  if (options.min_voted_coverage > 0.0 &&
      std::popcount(through.sectors) < options.min_voted_coverage * kVoterSectors)
    return {};
  const double r0 = options.voter_mode_radius
                        ? densest_radius(radii, options.min_radius_px, options.max_radius_px)
                        : median_of(radii);
  // voter_mode_radius: the median is the second seed (nth_element may reorder radii now).
  const double median_r = options.voter_mode_radius ? median_of(radii) : r0;
  const std::vector<cv::Point2d> support = support_points(voters, rows, peak, options, r0, passing);
  std::optional<Circle> c =
      refine_from_seeds(edges, peak, first_seed(peak, r0, support), median_r, options);
  rescue_weak(edges, options, c);
  if (!acceptable(c, options)) return {};
  PeakCircles out{*c};
  if (options.nested_circles)
    if (auto nested = nested_circle(edges, peak, radii, *c, options)) out.push_back(*nested);
  return out;
}

std::vector<Circle> select_circles(const EdgeMap& edges, std::vector<Circle> found,
                                   const CandidateOptions& options) {
  std::vector<Circle> kept =
      best_separated(std::move(found), options.min_separation_px, options.max_circles);
  if (options.refine && options.polish)
    polish_circles(edges, options.refine_params, options.min_score, kept);
  return kept;
}

}  // namespace stereoball::ball_detector
