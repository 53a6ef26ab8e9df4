// The Pixel-to-Pixel detector's driver: its parameters' checks, the entry points (detect,
// redetect, peaks) and the steps they run in order: edges, votes (p2p_voting.cpp), peaks, and
// circles from each peak (p2p_peak_circles.cpp); the halved-image and seeded searches are in
// p2p_seeds.cpp.
#include "ball_detector/core/p2p_detector.hpp"

#include "ball_detector/core/p2p_detector_internal.hpp"
#include "ball_detector/core/p2p_rules.hpp"
#include "ball_detector/core/voting.hpp"

#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

namespace stereoball::ball_detector {

using p2p_detail::kMaxK;
using p2p_detail::map_in_store;

namespace {

constexpr int kMaxCentreMarginPx = 4000;  // as max_radius_px: no centre is farther out
// coarse_to_fine: smaller images are searched whole.
constexpr int kCoarseMinSidePx = 64;

}  // namespace

// Makes view a rows x cols map of type in store's memory, growing store when it is too small. A
// map of a new size reuses the memory only while nothing else holds it (a copy in diagnostics
// keeps its values); a map of the same size stays as it is, as cv::Mat::create keeps it.
void p2p_detail::map_in_store(cv::Mat& store, cv::Mat& view, int rows, int cols, int type) {
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

}  // namespace stereoball::ball_detector
