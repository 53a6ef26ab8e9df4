// Searches that refine seed circles instead of voting at full resolution: coarse to fine (the
// halved image's candidates refined in windows of the full image) and seeds a caller gives
// (a tracked ball's predicted circle). Apart from the driver (p2p_detector.cpp): they share its
// refinement but none of its voting.
#include "ball_detector/core/p2p_detector.hpp"

#include "ball_detector/core/coarse_to_fine.hpp"
#include "ball_detector/core/p2p_detector_internal.hpp"

#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <memory>

namespace stereoball::ball_detector {
namespace {

// A coarse candidate's full-resolution window reaches this far beyond its circle (the clutter
// rings and the first refinement band fit).
constexpr double kWindowMarginPerRadius = 0.15;
constexpr double kWindowMarginPx = 5.0;
constexpr int kFineRefineRounds = 2;
constexpr double kEdgeMapOverheadPx = 2048.0;  // measured: 1500 (colour) to 3100 (grey)

}  // namespace

using p2p_detail::best_separated;
using p2p_detail::polish_refine_params;

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
