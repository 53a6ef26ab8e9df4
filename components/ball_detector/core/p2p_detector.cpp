#include "ball_detector/core/p2p_detector.hpp"

#include "ball_detector/core/coarse_to_fine.hpp"
#include "ball_detector/core/cpu_dispatch.hpp"
#include "ball_detector/core/fast_math.hpp"
#include "ball_detector/core/p2p_rules.hpp"
#include "ball_detector/core/voting.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>

namespace stereoball::ball_detector {
namespace {

constexpr int kMaxK = 31;                 // window rows are read as one 63-bit slice
constexpr int kMaxCentreMarginPx = 4000;  // as max_radius_px: no centre is farther out
constexpr double kRingSeedBelowScore = 0.8;
// nested_circle: the voters at another distance must be this many, and this share of all.
constexpr double kNestedMinVoters = 12.0;
constexpr double kNestedMinShare = 0.25;
// coarse_to_fine: smaller images are searched whole; a candidate's full-resolution window
// reaches this far beyond its circle (the clutter rings and the first refinement band fit).
constexpr int kCoarseMinSidePx = 64;
constexpr double kWindowMarginPerRadius = 0.15;
constexpr double kWindowMarginPx = 5.0;
constexpr int kFineRefineRounds = 2;
constexpr double kEdgeMapOverheadPx = 2048.0;  // measured: 1500 (colour) to 3100 (grey)

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

// The refinement options of PixelToPixelParams::polish (and rescue_weak_from).
RefineParams polish_refine_params(RefineParams refine) {
  refine.first_band_px = PixelToPixelParams::kPolishFirstBandPx;
  refine.robust_fit_floor_px = PixelToPixelParams::kPolishRobustFloorPx;
  return refine;
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

// Makes view a rows x cols map of type in store's memory, growing store when it is too small. A
// map of a new size reuses the memory only while nothing else holds it (a copy in diagnostics
// keeps its values); a map of the same size stays as it is, as cv::Mat::create keeps it.
void map_in_store(cv::Mat& store, cv::Mat& view, int rows, int cols, int type) {
  if (view.rows == rows && view.cols == cols && view.type() == type) return;
  view.release();
  const std::size_t total = static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols);
  if (total == 0) {
    view.create(rows, cols, type);
    return;
  }
  if (store.empty() || store.type() != type || store.total() < total || store.u->refcount > 1) {
    store.release();
    store.create(1, static_cast<int>(total), type);
  }
  view = store.colRange(0, static_cast<int>(total)).reshape(1, rows);
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

Status PixelToPixelParams::validate() const {
  if (auto e = edge.validate(); !e) return Error{"edge." + e.error()};
  if (k_values.empty()) return Error{"k_values must hold at least one k in [1, 31]"};
  for (int k : k_values)
    if (k < 1 || k > kMaxK) return Error{"k_values entries must be in [1, 31]"};
  if (box_size_px < 1 || box_size_px > 31 || box_size_px % 2 == 0)
    return Error{"box_size_px must be odd and in [1, 31]"};
  if (!(min_radius_px >= 0.0)) return Error{"min_radius_px must be >= 0"};
  if (!(max_radius_px > min_radius_px && max_radius_px <= 4000.0))
    return Error{"max_radius_px must be in (min_radius_px, 4000]"};
  if (max_circles < 1 || max_circles > 100) return Error{"max_circles must be in [1, 100]"};
  if (!(isolate_max_points_factor >= 1.0 && isolate_max_points_factor <= 64.0))
    return Error{"isolate_max_points_factor must be in [1, 64]"};
  if (!(min_separation_px >= 0.0)) return Error{"min_separation_px must be >= 0"};
  if (!(min_score >= 0.0 && min_score <= 1.0)) return Error{"min_score must be in [0, 1]"};
  if (min_peak_votes < 0) return Error{"min_peak_votes must be >= 0"};
  if (max_peaks_examined < 1 || max_peaks_examined > 1000)
    return Error{"max_peaks_examined must be in [1, 1000]"};
  if (!(min_relative_peak >= 0.0 && min_relative_peak <= 1.0))
    return Error{"min_relative_peak must be in [0, 1]"};
  if (!(refine_params.band_px > 0.0 && refine_params.band_px <= 10.0))
    return Error{"refine_params.band_px must be in (0, 10]"};
  if (!(refine_params.min_radial_cos >= 0.0 && refine_params.min_radial_cos <= 1.0))
    return Error{"refine_params.min_radial_cos must be in [0, 1]"};
  if (!(refine_params.first_band_px > 0.0 && refine_params.first_band_px <= 20.0))
    return Error{"refine_params.first_band_px must be in (0, 20]"};
  if (!(refine_params.robust_fit_floor_px >= 0.0 && refine_params.robust_fit_floor_px <= 10.0))
    return Error{"refine_params.robust_fit_floor_px must be in [0, 10]"};
  if (!(refine_params.clutter_ring_per_radius >= 0.0 &&
        refine_params.clutter_ring_per_radius <= 1.0))
    return Error{"refine_params.clutter_ring_per_radius must be in [0, 1]"};
  if (!(refine_params.clutter_min_radius_px >= 0.0 &&
        refine_params.clutter_min_radius_px <= 4000.0))
    return Error{"refine_params.clutter_min_radius_px must be in [0, 4000]"};
  if (!(refine_params.give_up_below >= 0.0 && refine_params.give_up_below <= 1.0))
    return Error{"refine_params.give_up_below must be in [0, 1]"};
  if (!(rescue_weak_from >= 0.0 && rescue_weak_from <= 1.0))
    return Error{"rescue_weak_from must be in [0, 1]"};
  if (!(coarse_min_score >= 0.0 && coarse_min_score <= 1.0))
    return Error{"coarse_min_score must be in [0, 1]"};
  if (!(coarse_min_voted_coverage >= 0.0 && coarse_min_voted_coverage <= 1.0))
    return Error{"coarse_min_voted_coverage must be in [0, 1]"};
  if (!(refine_params.min_inside_fraction >= 0.0 && refine_params.min_inside_fraction <= 1.0))
    return Error{"refine_params.min_inside_fraction must be in [0, 1]"};
  if (!(fine_below_radius_px >= 0.0 && fine_below_radius_px <= 4000.0))
    return Error{"fine_below_radius_px must be in [0, 4000]"};
  if (coarse_max_peaks_examined < 0 || coarse_max_peaks_examined > 1000)
    return Error{"coarse_max_peaks_examined must be in [0, 1000]"};
  if (fine_max_peaks_examined < 0 || fine_max_peaks_examined > 1000)
    return Error{"fine_max_peaks_examined must be in [0, 1000]"};
  if (stop_after_missed_peaks < 0 || stop_after_missed_peaks > 1000)
    return Error{"stop_after_missed_peaks must be in [0, 1000]"};
  if (fine_stop_after_missed_peaks < 0 || fine_stop_after_missed_peaks > 1000)
    return Error{"fine_stop_after_missed_peaks must be in [0, 1000]"};
  if (fine_below_radius_px > 0.0) {
    if (fine_k_values.empty()) return Error{"fine_k_values must hold at least one k in [1, 31]"};
    for (int k : fine_k_values)
      if (k < 1 || k > kMaxK) return Error{"fine_k_values entries must be in [1, 31]"};
  }
  return {};
}

PixelToPixelDetector::PixelToPixelDetector(const PixelToPixelParams& params) : params_(params) {
  for (int& k : params_.k_values) k = std::clamp(k, 1, kMaxK);
  if (params_.k_values.empty()) params_.k_values = {5};
  for (int& k : params_.fine_k_values) k = std::clamp(k, 1, kMaxK);
  if (params_.fine_k_values.empty()) params_.fine_k_values = {3};
  params_.box_size_px = std::clamp(params_.box_size_px | 1, 1, 31);
  // Vote lines join two points of a window of half size k: |nx|, |ny| <= 2 k.
  const int max_k =
      std::max(std::ranges::max(params_.k_values), std::ranges::max(params_.fine_k_values));
  direction_span_ = 2 * max_k;
  directions_.resize(
      static_cast<std::size_t>((2 * direction_span_ + 1) * (2 * direction_span_ + 1)));
  voters_.reserve(8192);
  lines_.reserve(8192);
}

void PixelToPixelDetector::vote(int k) {
  vote_rows(k, 0, edges_.bits.height(), [this](float cx, float cy, int nx, int ny) {
    lines_.push_back({cx, cy, nx, ny});
    plot(lines_.back());
  });
}

int PixelToPixelDetector::isolate_max_points_of(int n) const {
  return params_.isolate_arc ? static_cast<int>(params_.isolate_max_points_factor * n) : 0;
}

template <typename F>
void PixelToPixelDetector::for_each_window_centre(int k, int y_begin, int y_end, F&& f) const {
  const BitImage& bits = edges_.bits;
  const int w = bits.width();
  const int y_last = std::min(bits.height() - k, y_end);
  for (int y = std::max(k, y_begin); y < y_last; ++y)
    bits.for_each_set_in_row(y, [&](int x) {
      if (x >= k && x < w - k) f(x, y);
    });
}

template <typename Emit>
void PixelToPixelDetector::vote_rows(int k, int y_begin, int y_end, Emit&& emit) {
  // The packed windows' loops unrolled for each k (p2p_rules.hpp).
  if (k == 1) return vote_packed<1>(y_begin, y_end, emit);
  if (k == 2) return vote_packed<2>(y_begin, y_end, emit);
  if (k == 3) return vote_packed<3>(y_begin, y_end, emit);
  static_assert(kPackedMaxK == 3);
#if SB_WIDE_WINDOWS
  if (k == 4) return vote_wide<4>(y_begin, y_end, emit);
  if (k == 5) return vote_wide<5>(y_begin, y_end, emit);
  static_assert(kWideMaxK == 5);
#endif
  const BitImage& bits = edges_.bits;
  std::array<std::uint64_t, 2 * kMaxK + 1> mask{};
  std::array<std::uint64_t, 2 * kMaxK + 1> rows{};
  const int n = 2 * k + 1;
  const int isolate_max_points = isolate_max_points_of(n);
  for_each_window_centre(k, y_begin, y_end, [&](int x, int y) {
    // The window's rows are read once, step 4's count taken as they are (a popcount per
    // row): far cheaper than collecting points.
    const auto window_bits = std::span(rows.data(), n);
    const int count = window_rows(bits, x, y, k, window_bits);
    // Steps 5-7 read the chord ends straight off the row masks (vote_line_of_rows).
    std::optional<VoteLine> line;
    if (window_count_ok(count, k)) {
      line = vote_line_of_rows(window_bits, k);
    } else if (count > n && count <= isolate_max_points) {
      // Addition: judge the arc through O alone when other edges share the window.
      const int connected = connected_rows(window_bits, k, mask, n);
      // O's aligned component lies inside its component: fewer than n points leave it short too.
      if (connected != n && (connected < n || !params_.isolate_by_orientation ||
                             !isolate_along_orientation(x, y, k, window_bits, mask)))
        return;
      line = vote_line_of_rows(std::span<const std::uint64_t>(mask.data(), n), k);
    } else {
      return;
    }
    if (!line) return;
    // C lies on the half-pixel grid: exact in float for any image size we take.
    emit(static_cast<float>(x + 0.5 * line->c2x), static_cast<float>(y + 0.5 * line->c2y), line->nx,
         line->ny);
  });
}

template <int k, typename Emit>
void PixelToPixelDetector::vote_packed(int y_begin, int y_end, Emit& emit) {
  // vote_rows() for windows that fit one word (p2p_rules.hpp): the same rules on the same points,
  // each a few word operations instead of a loop over rows.
  const BitImage& bits = edges_.bits;
  const int n = 2 * k + 1;
  const int isolate_max_points = isolate_max_points_of(n);
  for_each_window_centre(k, y_begin, y_end, [&](int x, int y) {
    const std::uint64_t window = packed_window(bits, x, y, k);
    const int count = std::popcount(window);
    std::uint64_t arc = window;
    if (count == n) {
      // The count rule holds: the whole window is the arc.
    } else if (count > n && count <= isolate_max_points) {
      // Addition: judge the arc through O alone when other edges share the window.
      const int connected = connected_packed(window, k, arc, n);
      if (connected != n && (connected < n || !params_.isolate_by_orientation ||
                             !isolate_packed<k>(x, y, window, arc)))
        return;
    } else {
      return;
    }
    const std::optional<VoteLine> line = vote_line_packed(arc, k);
    if (!line) return;
    emit(static_cast<float>(x + 0.5 * line->c2x), static_cast<float>(y + 0.5 * line->c2y), line->nx,
         line->ny);
  });
}

template <int k>
bool PixelToPixelDetector::isolate_packed(int x, int y, std::uint64_t window, std::uint64_t& arc) {
  // isolate_along_orientation on a packed window: the points within the slack of O's
  // orientation, then their component through O.
  if (!orientation_ready_) build_orientation_planes();
  const BitImage& near = near_orientation_[static_cast<std::size_t>(
      orientation_bin(edges_.dx.at<short>(y, x), edges_.dy.at<short>(y, x)))];
  const std::uint64_t aligned = window & packed_window(near, x, y, k);
  const int n = 2 * k + 1;
  if (std::popcount(aligned) < n || aligned == window) return false;
  return connected_packed(aligned, k, arc, n) == n;
}

#if SB_WIDE_WINDOWS
template <int k, typename Emit>
void PixelToPixelDetector::vote_wide(int y_begin, int y_end, Emit& emit) {
  // vote_packed() for windows of up to 11 x 11 pixels (p2p_rules.hpp): a 128-bit word instead
  // of a mask per row, the component grown a ring at a time instead of row by row.
  const BitImage& bits = edges_.bits;
  constexpr int n = 2 * k + 1;
  const int isolate_max_points = isolate_max_points_of(n);
  for_each_window_centre(k, y_begin, y_end, [&](int x, int y) {
    const WideWindow window = wide_window<k>(bits, x, y);
    const int count = wide_detail::popcount_wide(window);
    WideWindow arc = window;
    if (count == n) {
      // The count rule holds: the whole window is the arc.
    } else if (count > n && count <= isolate_max_points) {
      // Addition: judge the arc through O alone when other edges share the window.
      const int connected = connected_wide<k>(window, arc, n);
      if (connected != n &&
          (connected < n || !params_.isolate_by_orientation || !isolate_wide<k>(x, y, window, arc)))
        return;
    } else {
      return;
    }
    const std::optional<VoteLine> line = vote_line_wide<k>(arc);
    if (!line) return;
    emit(static_cast<float>(x + 0.5 * line->c2x), static_cast<float>(y + 0.5 * line->c2y), line->nx,
         line->ny);
  });
}

template <int k>
bool PixelToPixelDetector::isolate_wide(int x, int y, WideWindow window, WideWindow& arc) {
  // isolate_packed on a wide window.
  if (!orientation_ready_) build_orientation_planes();
  const BitImage& near = near_orientation_[static_cast<std::size_t>(
      orientation_bin(edges_.dx.at<short>(y, x), edges_.dy.at<short>(y, x)))];
  const WideWindow aligned = window & wide_window<k>(near, x, y);
  constexpr int n = 2 * k + 1;
  if (wide_detail::popcount_wide(aligned) < n || aligned == window) return false;
  return connected_wide<k>(aligned, arc, n) == n;
}
#endif

// Inlined into both callers: the one-run plot() costs what it did before shares existed.
[[gnu::always_inline]] inline void PixelToPixelDetector::plot_into(const VoteLineAt& line,
                                                                   cv::Mat& accumulator,
                                                                   std::int64_t& rays_plotted,
                                                                   std::int64_t& increments,
                                                                   std::vector<Voter>& voters) {
  // A ray meets a cell once: while fewer rays than a cell holds have gone into the zeroed map,
  // none is full and the increments need no saturation test.
  const bool may_be_full = rays_plotted++ >= 0xFFFF;
  const LineDirection& dir = line_direction(line.nx, line.ny);
  increments += plot_ray(accumulator, static_cast<double>(line.cx) + margin_px_,
                         static_cast<double>(line.cy) + margin_px_, dir.ray, radii_.min_px,
                         radii_.max_px, may_be_full);
  voters.push_back({line.cx, line.cy, dir.unit_x, dir.unit_y});
}

void PixelToPixelDetector::plot(const VoteLineAt& line) {
  plot_into(line, accumulator_, rays_plotted_, diag_.increments, voters_);
}

void PixelToPixelDetector::plot(const VoteLineAt& line, cv::Mat& accumulator, VoteShare& share) {
  plot_into(line, accumulator, share.rays_plotted, share.increments, share.voters);
}

void PixelToPixelDetector::fill_directions() {
  const int span = direction_span_;
  for (int nx = -span; nx <= span; ++nx)
    for (int ny = -span; ny <= span; ++ny) (void)line_direction(nx, ny);
}

const PixelToPixelDetector::LineDirection& PixelToPixelDetector::line_direction(int nx, int ny) {
  // A few hundred directions recur over tens of thousands of lines: the square roots and
  // divisions are done once per direction, with the same operations (the same bits).
  const int span = direction_span_;
  const bool in_table = nx >= -span && nx <= span && ny >= -span && ny <= span;
  LineDirection& d =
      in_table ? directions_[static_cast<std::size_t>((nx + span) * (2 * span + 1) + ny + span)]
               : direction_scratch_;
  if (d.ready) return d;
  d.ray = ray_direction(nx, ny);
  const float norm = fast_hypot(static_cast<float>(nx), static_cast<float>(ny));
  d.unit_x = nx / norm;
  d.unit_y = ny / norm;
  d.ready = in_table;
  return d;
}

void PixelToPixelDetector::build_orientation_planes() {
  near_orientation_planes(edges_, near_orientation_);
  orientation_ready_ = true;
}

bool PixelToPixelDetector::isolate_along_orientation(int x, int y, int k,
                                                     std::span<const std::uint64_t> window,
                                                     std::span<std::uint64_t> mask) {
  if (!orientation_ready_) build_orientation_planes();
  const int n = 2 * k + 1;
  // The window's points within the slack of O's orientation: one AND per row with O's plane.
  const BitImage& near = near_orientation_[static_cast<std::size_t>(
      orientation_bin(edges_.dx.at<short>(y, x), edges_.dy.at<short>(y, x)))];
  std::array<std::uint64_t, 2 * kMaxK + 1> aligned;  // rows [0, n) written below, no others read
  int count = 0;
  std::uint64_t dropped = 0;
  for (int i = 0; i < n; ++i) {
    const std::uint64_t all = window[static_cast<std::size_t>(i)];
    const std::uint64_t kept =
        all & (n <= 57 ? near.short_bits(y - k + i, x - k, n) : near.bits(y - k + i, x - k, n));
    aligned[static_cast<std::size_t>(i)] = kept;
    dropped |= all ^ kept;
    count += std::popcount(kept);
  }
  // Nothing dropped: the same window whose component the caller found not to be n points.
  if (count < n || dropped == 0) return false;
  return connected_rows(std::span<const std::uint64_t>(aligned.data(), static_cast<std::size_t>(n)),
                        k, mask, n) == n;
}

void PixelToPixelDetector::start(const std::optional<SearchHints>& hints) {
  diag_ = DetectionDiagnostics{};
  peak_ratio_done_ = false;
  votes_ready_ = false;
  voters_.clear();
  radii_ = {params_.min_radius_px, params_.max_radius_px};
  min_inside_fraction_ = params_.refine_params.min_inside_fraction;
  margin_px_ = 0;
  if (hints) {
    radii_.min_px = std::max(radii_.min_px, hints->radii.min_px);
    radii_.max_px = std::min(radii_.max_px, hints->radii.max_px);
    if (hints->min_inside_fraction >= 0.0)
      min_inside_fraction_ = std::min(1.0, hints->min_inside_fraction);
    // A centre farther out than the largest radius searched leaves nothing of its circle in
    // view: no cell is needed there (and the accumulator stays bounded).
    const int widest = static_cast<int>(std::ceil(std::max(0.0, radii_.max_px)));
    margin_px_ = std::clamp(hints->centre_margin_px, 0, std::min(widest, kMaxCentreMarginPx));
  }
}

std::vector<Circle> PixelToPixelDetector::detect(const cv::Mat& bgr_or_grey) {
  if (params_.coarse_to_fine && bgr_or_grey.cols >= kCoarseMinSidePx &&
      bgr_or_grey.rows >= kCoarseMinSidePx)
    return params_.fine_below_radius_px > params_.min_radius_px
               ? detect_multi_scale(bgr_or_grey)
               : detect_coarse_to_fine(bgr_or_grey);
  if (!cast_votes(bgr_or_grey)) return {};
  return circles_of_votes();
}

bool PixelToPixelDetector::cast_votes(const cv::Mat& bgr_or_grey, const VoteTasks& tasks) {
  start(std::nullopt);
  edges_ready_ = false;
  orientation_ready_ = false;  // planes of the previous edge map
  if (!validate_image(bgr_or_grey).ok()) return false;
  compute_edge_map(bgr_or_grey, params_.edge, edges_);
  edges_ready_ = true;
  vote_on_edges(tasks);
  return true;
}

bool PixelToPixelDetector::cast_votes_on_edges(EdgeMap& edges, const VoteTasks& tasks) {
  start(std::nullopt);
  orientation_ready_ = false;  // planes of the previous edge map
  std::swap(edges_, edges);
  edges_ready_ = !edges_.edges.empty();
  if (!edges_ready_) return false;
  vote_on_edges(tasks);
  return true;
}

bool PixelToPixelDetector::cast_votes_on_last_edges(const VoteTasks& tasks) {
  if (!edges_ready_) return false;
  start(std::nullopt);
  // The orientation planes, if built, are this edge map's: still valid.
  vote_on_edges(tasks);
  return true;
}

bool PixelToPixelDetector::cast_votes_on_last_edges(const SearchHints& hints,
                                                    const VoteTasks& tasks) {
  if (!edges_ready_) return false;
  start(hints);
  vote_on_edges(tasks);
  return true;
}

void PixelToPixelDetector::forget_hints() {
  radii_ = {params_.min_radius_px, params_.max_radius_px};
  min_inside_fraction_ = params_.refine_params.min_inside_fraction;
}

bool PixelToPixelDetector::find_edges(const cv::Mat& bgr_or_grey) {
  start(std::nullopt);
  edges_ready_ = false;
  orientation_ready_ = false;
  lines_.clear();  // a redetect of this image plots nothing
  if (!validate_image(bgr_or_grey).ok()) return false;
  compute_edge_map(bgr_or_grey, params_.edge, edges_);
  edges_ready_ = true;
  return true;
}

std::vector<Circle> PixelToPixelDetector::circles_of_votes() {
  if (!votes_ready_) return {};
  return circles_on(edges_);
}

std::vector<Circle> PixelToPixelDetector::detect(const cv::Mat& bgr_or_grey,
                                                 const EdgeThresholds& thresholds) {
  start(std::nullopt);
  edges_ready_ = false;
  orientation_ready_ = false;  // planes of the previous edge map
  if (!validate_image(bgr_or_grey).ok()) return {};
  compute_edge_map(bgr_or_grey, params_.edge, thresholds.canny, thresholds.denoise, edges_);
  edges_ready_ = true;
  return detect_on_edges();
}

std::vector<Circle> PixelToPixelDetector::detect(const cv::Mat& bgr_or_grey,
                                                 const EdgeThresholds& thresholds,
                                                 const SearchHints& hints) {
  if (!edges_with_hints(bgr_or_grey, thresholds, hints)) return {};
  return detect_on_edges();
}

bool PixelToPixelDetector::edges_with_hints(const cv::Mat& bgr_or_grey,
                                            const EdgeThresholds& thresholds,
                                            const SearchHints& hints) {
  if (!begin_edge_step(bgr_or_grey, hints)) return false;
  compute_edge_map(bgr_or_grey, params_.edge, thresholds.canny, thresholds.denoise, edges_);
  edges_ready_ = true;
  return true;
}

bool PixelToPixelDetector::begin_edge_step(const cv::Mat& image, const SearchHints& hints) {
  start(hints);
  edges_ready_ = false;
  orientation_ready_ = false;  // planes of the previous edge map
  return validate_image(image).ok() && radii_.max_px > radii_.min_px;
}

std::vector<Circle> PixelToPixelDetector::redetect(const SearchHints& hints) {
  return redetect_from(*this, hints);
}

std::vector<Circle> PixelToPixelDetector::redetect_from(const PixelToPixelDetector& source,
                                                        const SearchHints& hints) {
  if (!revote_from(source, hints)) return {};
  return circles_on(source.edges_);
}

std::optional<int> PixelToPixelDetector::peaks_from(const PixelToPixelDetector& source,
                                                    const SearchHints& hints) {
  if (!revote_from(source, hints)) return std::nullopt;
  return peaks_on(source.edges_);
}

bool PixelToPixelDetector::revote_from(const PixelToPixelDetector& source,
                                       const SearchHints& hints) {
  start(hints);
  if (!source.edges_ready_ || !(radii_.max_px > radii_.min_px)) return false;
  // Which points vote and along which line does not depend on the radii (steps 2-6): only the
  // plotting (step 7) is redone, in the same order, so the accumulator is the same cell by cell.
  const cv::Size size = source.edges_.edges.size();
  map_in_store(accumulator_store_, accumulator_, size.height + 2 * margin_px_,
               size.width + 2 * margin_px_, CV_16UC1);
  accumulator_.setTo(0);
  rays_plotted_ = 0;
  for (const VoteLineAt& line : source.lines_) plot(line);
  return true;
}

std::vector<Circle> PixelToPixelDetector::detect_on_edges() {
  vote_on_edges();
  return circles_on(edges_);
}

void PixelToPixelDetector::vote_on_edges(const VoteTasks& tasks) {
  const cv::Size size = edges_.edges.size();
  map_in_store(accumulator_store_, accumulator_, size.height + 2 * margin_px_,
               size.width + 2 * margin_px_, CV_16UC1);
  rays_plotted_ = 0;
  lines_.clear();
  if (tasks.run && tasks.shares > 1) {
    vote_in_shares(tasks);
  } else {
    accumulator_.setTo(0);
    for (int k : params_.k_values) vote(k);
  }
  votes_ready_ = true;
}

void PixelToPixelDetector::vote_in_shares(const VoteTasks& tasks) {
  const int n = std::min(tasks.shares, VoteTasks::kMaxVoteShares);
  // What the shares read and would otherwise make on first use is made first: they only read.
  // Every line's direction lies in the table (|nx|, |ny| <= 2 k <= direction_span_), never in
  // its shared scratch.
  if (params_.isolate_arc && params_.isolate_by_orientation && !orientation_ready_)
    build_orientation_planes();
  fill_directions();
  const std::vector<std::vector<int>> rows = share_rows(n);
  if (shares_.size() < static_cast<std::size_t>(n)) shares_.resize(static_cast<std::size_t>(n));
  for (int s = 1; s < n; ++s) {
    VoteShare& share = shares_[static_cast<std::size_t>(s)];
    map_in_store(share.store, share.accumulator, accumulator_.rows, accumulator_.cols, CV_16UC1);
  }
  tasks.run(n, [&](int s) { vote_share(s, rows); });
  join_shares(n);
}

std::vector<std::vector<int>> PixelToPixelDetector::share_rows(int n) const {
  // A share's time follows its edge points (each is a window to judge), not its rows.
  const BitImage& bits = edges_.bits;
  const int h = bits.height();
  const int words = (bits.width() + 63) / 64;
  std::vector<std::int64_t> before(static_cast<std::size_t>(h) + 1, 0);  // points in rows < y
  for (int y = 0; y < h; ++y) {
    std::int64_t count = 0;
    for (int i = 0; i < words; ++i) count += std::popcount(bits.row(y)[i]);
    before[static_cast<std::size_t>(y) + 1] = before[static_cast<std::size_t>(y)] + count;
  }
  std::vector<std::vector<int>> rows;
  for (int k : params_.k_values) {
    const int first = std::min(k, h), last = std::max(first, h - k);
    const std::int64_t from = before[static_cast<std::size_t>(first)];
    const std::int64_t total = before[static_cast<std::size_t>(last)] - from;
    std::vector<int> bounds{first};
    for (int s = 1; s < n; ++s) {
      const std::int64_t target = from + total * s / n;
      const auto at =
          std::lower_bound(before.begin() + bounds.back(), before.begin() + last, target);
      bounds.push_back(static_cast<int>(at - before.begin()));
    }
    bounds.push_back(last);
    rows.push_back(std::move(bounds));
  }
  return rows;
}

void PixelToPixelDetector::vote_share(int s, const std::vector<std::vector<int>>& rows) {
  VoteShare& share = shares_[static_cast<std::size_t>(s)];
  cv::Mat& accumulator = s == 0 ? accumulator_ : share.accumulator;
  accumulator.setTo(0);
  share.lines.clear();
  share.voters.clear();
  share.k_ends.clear();
  share.rays_plotted = 0;
  share.increments = 0;
  for (std::size_t j = 0; j < params_.k_values.size(); ++j) {
    vote_rows(params_.k_values[j], rows[j][static_cast<std::size_t>(s)],
              rows[j][static_cast<std::size_t>(s) + 1], [&](float cx, float cy, int nx, int ny) {
                share.lines.push_back({cx, cy, nx, ny});
                plot(share.lines.back(), accumulator, share);
              });
    share.k_ends.push_back(share.lines.size());
  }
}

void PixelToPixelDetector::join_shares(int n) {
  // Lines and voters in the order one task would have made them: k by k, rows in order.
  voters_.clear();
  for (std::size_t j = 0; j < params_.k_values.size(); ++j) {
    for (int s = 0; s < n; ++s) {
      const VoteShare& share = shares_[static_cast<std::size_t>(s)];
      const auto begin = static_cast<std::ptrdiff_t>(j == 0 ? 0 : share.k_ends[j - 1]);
      const auto end = static_cast<std::ptrdiff_t>(share.k_ends[j]);
      lines_.insert(lines_.end(), share.lines.begin() + begin, share.lines.begin() + end);
      voters_.insert(voters_.end(), share.voters.begin() + begin, share.voters.begin() + end);
    }
  }
  // Each cell holds min(votes, 0xFFFF), as one map plotted with saturation does.
  for (int s = 0; s < n; ++s) {
    const VoteShare& share = shares_[static_cast<std::size_t>(s)];
    rays_plotted_ += share.rays_plotted;
    diag_.increments += share.increments;
    if (s > 0) cv::add(accumulator_, share.accumulator, accumulator_);  // saturating for CV_16U
  }
}

std::vector<Circle> PixelToPixelDetector::circles_on(const EdgeMap& edges) {
  const int n = peaks_on(edges);
  std::vector<PeakCircles> per_peak(static_cast<std::size_t>(n));
  const int stop_after = params_.stop_after_missed_peaks;
  int missed_in_row = 0;
  for (int i = 0; i < n; ++i) {
    PeakCircles& circles = per_peak[static_cast<std::size_t>(i)];
    circles = refine_peak(i);
    missed_in_row = circles.empty() ? missed_in_row + 1 : 0;
    if (stop_after > 0 && missed_in_row >= stop_after) break;
  }
  return select_circles(per_peak);
}

int PixelToPixelDetector::find_peaks_of_votes() {
  if (!votes_ready_) {
    peaks_.clear();
    return 0;
  }
  return peaks_on(edges_);
}

int PixelToPixelDetector::peaks_on(const EdgeMap& edges) {
  peaks_.clear();
  peak_edges_ = &edges;
  map_in_store(smoothed_store_, smoothed_, accumulator_.rows, accumulator_.cols, CV_32SC1);
  const double max_v = box_filter(accumulator_, params_.box_size_px, smoothed_, row_maxima_);
  const cv::Mat& smoothed = smoothed_;
  diag_.edges = edges.edges;
  diag_.accumulator = smoothed;
  diag_.voters = static_cast<std::int64_t>(voters_.size());
  const float floor_v = static_cast<float>(
      std::max<double>(params_.min_peak_votes, params_.min_relative_peak * max_v));
  if (max_v < params_.min_peak_votes || max_v <= 0.0) return 0;
  peaks_ = find_peaks(smoothed, floor_v, params_.min_separation_px,
                      std::max(params_.max_peaks_examined, params_.max_circles), row_maxima_);
  for (Peak& p : peaks_) {  // back to image coordinates (outside the image with a margin)
    p.x -= margin_px_;
    p.y -= margin_px_;
  }
  CandidateOptions& opt = candidate_options_;
  opt = candidate_options_of(params_, radii_);
  opt.refine_params.min_inside_fraction = min_inside_fraction_;
  opt.polish = params_.polish;
  opt.rescue_weak_from = params_.rescue_weak_from;
  opt.nested_circles = true;
  opt.min_voted_coverage = voted_coverage_gate_;
  opt.voter_mode_radius = voter_mode_radius_;
  voter_rows_ = VoterRows(voters_);
  return static_cast<int>(peaks_.size());
}

PeakCircles PixelToPixelDetector::refine_peak(int i) const {
  if (i < 0 || i >= static_cast<int>(peaks_.size()) || !peak_edges_) return {};
  return circle_from_peak(*peak_edges_, voters_, voter_rows_, peaks_[static_cast<std::size_t>(i)],
                          candidate_options_);
}

std::vector<Circle> PixelToPixelDetector::select_circles(
    const std::vector<PeakCircles>& per_peak) const {
  std::vector<Circle> found;
  for (const auto& circles : per_peak) found.insert(found.end(), circles.begin(), circles.end());
  return ball_detector::select_circles(*peak_edges_, std::move(found), candidate_options_);
}

const DetectionDiagnostics* PixelToPixelDetector::diagnostics() const {
  if (!peak_ratio_done_ && !diag_.accumulator.empty()) {
    diag_.peak_to_mean = peak_to_mean(diag_.accumulator);
    peak_ratio_done_ = true;
  }
  return &diag_;
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

// The best circles first, none within min_separation_px of a better one, at most max_circles.
std::vector<Circle> best_separated(std::vector<Circle> found, double min_separation_px,
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

}  // namespace

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

namespace {

// coarse_to_fine: the halved image's settings. Each k keeps its meaning: a window of the same
// size in the scene, so the same radii pass the count rule (a window must hold an arc, not half
// of a small circle).
PixelToPixelParams halved_image_params(const PixelToPixelParams& full) {
  PixelToPixelParams p = full;
  p.coarse_to_fine = false;
  p.k_values.clear();
  for (int k : full.k_values)
    if (const int half_k = (k + 1) / 2;
        std::find(p.k_values.begin(), p.k_values.end(), half_k) == p.k_values.end())
      p.k_values.push_back(half_k);
  p.min_radius_px = 0.5 * full.min_radius_px;
  p.max_radius_px = 0.5 * full.max_radius_px;
  p.min_separation_px = 0.5 * full.min_separation_px;
  p.min_peak_votes = (full.min_peak_votes + 1) / 2;  // half the circumference votes
  p.min_score = full.coarse_min_score;
  // Every candidate goes on to full resolution, where the best max_circles are kept.
  p.max_circles = std::max(full.max_circles, full.max_peaks_examined);
  if (full.coarse_max_peaks_examined > 0) {
    p.max_peaks_examined = full.coarse_max_peaks_examined;
    p.max_circles = full.coarse_max_peaks_examined;
  }
  p.polish = false;  // the full-resolution refinement polishes
  p.refine_params.camera.reset();
  p.refine_params.give_up_below = full.coarse_min_score;
  // Clutter is judged at full resolution, where the rings are measured on sharper edges.
  p.refine_params.clutter_ring_per_radius = 0.0;
  return p;
}

// The halved image's candidates as full-resolution seeds, each with the window of the image
// it is refined in (its circle and a margin), the region they span and their total area.
struct CoarseWindows {
  std::vector<Circle> seeds;
  std::vector<cv::Rect> windows;
  cv::Rect span;
  double total_area = 0.0;
};

CoarseWindows coarse_windows(const std::vector<Circle>& candidates, cv::Size image_size) {
  CoarseWindows out;
  const cv::Rect whole(cv::Point(0, 0), image_size);
  for (const Circle& c : candidates) {
    // Pixel (i, j) of the halved image is the mean of pixels 2i, 2i + 1 (and 2j, 2j + 1).
    const Circle seed{2.0 * c.x_px + 0.5, 2.0 * c.y_px + 0.5, 2.0 * c.radius_px, 0.0};
    const double reach = seed.radius_px * (1.0 + kWindowMarginPerRadius) + kWindowMarginPx;
    const cv::Point top_left(static_cast<int>(std::floor(seed.x_px - reach)),
                             static_cast<int>(std::floor(seed.y_px - reach)));
    const cv::Point bottom_right(static_cast<int>(std::ceil(seed.x_px + reach)) + 1,
                                 static_cast<int>(std::ceil(seed.y_px + reach)) + 1);
    const cv::Rect window = cv::Rect(top_left, bottom_right) & whole;
    if (window.width < 3 || window.height < 3) continue;
    out.seeds.push_back(seed);
    out.windows.push_back(window);
    out.span = out.span.area() == 0 ? window : (out.span | window);
    out.total_area += window.area();
  }
  return out;
}

}  // namespace

std::vector<Circle> PixelToPixelDetector::detect_coarse_to_fine(const cv::Mat& image) {
  return detect_coarse_to_fine(image, nullptr);
}

std::vector<Circle> PixelToPixelDetector::detect_coarse_to_fine(const cv::Mat& image,
                                                                const EdgeMap* whole_edges) {
  start(std::nullopt);
  edges_ready_ = false;  // no full-resolution map of the whole image: redetect finds nothing
  orientation_ready_ = false;
  if (!validate_image(image).ok()) return {};
  if (!coarse_) {
    coarse_ = std::make_unique<PixelToPixelDetector>(halved_image_params(params_));
    coarse_->voted_coverage_gate_ = params_.coarse_min_voted_coverage;
    coarse_->voter_mode_radius_ = true;
  }
  // An even size halves exactly (each pixel the rounded mean of a 2x2 block, halve_image).
  const cv::Mat even = image(cv::Rect(0, 0, image.cols & ~1, image.rows & ~1));
  halve_image(even, half_);
  const std::vector<Circle> candidates = coarse_->detect(half_);
  diag_ = coarse_->diag_;  // the halved image's edges and votes
  const CoarseWindows w = coarse_windows(candidates, image.size());
  std::vector<Circle> found;
  if (w.seeds.empty()) return found;
  if (whole_edges && whole_edges->edges.size() == image.size()) {
    const cv::Rect whole(cv::Point(0, 0), image.size());
    for (const Circle& seed : w.seeds)
      if (const auto fine = refine_in_window(*whole_edges, whole, seed)) found.push_back(*fine);
    return best_separated(std::move(found), params_.min_separation_px, params_.max_circles);
  }
  // Many or large windows: one edge map of the region they span costs less than one each,
  // each map costing about as much as kEdgeMapOverheadPx more pixels (calls, allocations,
  // histogram); its thresholds are then those of that region.
  const bool one_map =
      w.span.area() <= w.total_area + kEdgeMapOverheadPx * static_cast<double>(w.seeds.size());
  if (one_map) compute_edge_map(image(w.span), params_.edge, window_edges_);
  for (std::size_t i = 0; i < w.seeds.size(); ++i) {
    const cv::Rect& window = one_map ? w.span : w.windows[i];
    // A window's own edge thresholds: it holds the outline and its surroundings, whose
    // contrast is what the outline must stand out from.
    if (!one_map) compute_edge_map(image(window), params_.edge, window_edges_);
    if (const auto fine = refine_in_window(window_edges_, window, w.seeds[i]))
      found.push_back(*fine);
  }
  return best_separated(std::move(found), params_.min_separation_px, params_.max_circles);
}

std::vector<Circle> PixelToPixelDetector::keep_best_separated(std::vector<Circle> found) const {
  return best_separated(std::move(found), params_.min_separation_px, params_.max_circles);
}

std::optional<Circle> PixelToPixelDetector::refine_in_window(const EdgeMap& edges,
                                                             const cv::Rect& window,
                                                             Circle seed) const {
  seed.x_px -= window.x;
  seed.y_px -= window.y;
  RefineParams refine = params_.refine_params;
  refine.give_up_below = std::max(refine.give_up_below, params_.min_score);
  // The seed is within a pixel or two (the halved image's refined circle): two rounds before
  // scoring. With polish on they are the polish's robust rounds from its wider band (the only
  // refinement needed), else least squares from first_band_px.
  refine.iterations = kFineRefineRounds;
  if (params_.polish) {
    refine.first_band_px = PixelToPixelParams::kPolishFirstBandPx;
    refine.robust_fit_floor_px = PixelToPixelParams::kPolishRobustFloorPx;
  }
  std::optional<Circle> c = refine_circle(edges, seed, refine);
  if (!c || c->score < params_.min_score) return std::nullopt;
  if (c->radius_px < params_.min_radius_px || c->radius_px > params_.max_radius_px)
    return std::nullopt;
  c->x_px += window.x;
  c->y_px += window.y;
  return c;
}

std::vector<Circle> PixelToPixelDetector::detect_at_seeds(const cv::Mat& bgr_or_grey,
                                                          const EdgeThresholds& thresholds,
                                                          const SearchHints& hints,
                                                          std::span<const Circle> seeds) {
  if (!edges_with_hints(bgr_or_grey, thresholds, hints)) return {};
  return refine_seeds(seeds);
}

std::vector<Circle> PixelToPixelDetector::detect_at_seeds_without_brightness(
    const cv::Mat& bgr, const SearchHints& hints, std::span<const Circle> seeds) {
  if (!begin_edge_step(bgr, hints) || bgr.type() != CV_8UC3) return {};
  compute_brightness_free_edge_map(bgr, params_.edge, brightness_free_, edges_);
  edges_ready_ = true;
  return refine_seeds(seeds);
}

std::vector<Circle> PixelToPixelDetector::refine_seeds(std::span<const Circle> seeds) const {
  RefineParams refine = params_.refine_params;
  refine.min_inside_fraction = min_inside_fraction_;
  // The robust fit from the wider band: a prediction is off by a few pixels, a peak by one or
  // two; a seed that cannot reach min_score is dropped at its first round.
  RefineParams robust = polish_refine_params(refine);
  robust.give_up_below = std::max(robust.give_up_below, params_.min_score);
  std::vector<Circle> found;
  for (const Circle& seed : seeds) {
    std::optional<Circle> c = params_.refine ? refine_circle(edges_, seed, robust) : seed;
    if (!params_.refine) c->score = score_circle(edges_, seed, refine);
    if (c && params_.refine && params_.polish)
      if (const auto polished = refine_circle(edges_, *c, robust);
          polished && polished->score >= params_.min_score)
        c = polished;
    if (c && c->score >= params_.min_score && c->radius_px >= radii_.min_px &&
        c->radius_px <= radii_.max_px)
      found.push_back(*c);
  }
  return best_separated(std::move(found), params_.min_separation_px, params_.max_circles);
}

}  // namespace stereoball::ball_detector
