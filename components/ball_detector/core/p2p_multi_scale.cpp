// PixelToPixelParams::fine_below_radius_px: small circles at full resolution, the others coarse
// to fine, the two lists merged.

#include "ball_detector/core/p2p_detector.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace stereoball::ball_detector {
namespace {

// The full-resolution search reaches this far above fine_below_radius_px: a circle at the
// boundary is found by either search, and the better of the two is kept.
constexpr double kFineOverlap = 1.25;

}  // namespace

PixelToPixelParams PixelToPixelParams::small_circle_search() const {
  PixelToPixelParams p = *this;
  p.coarse_to_fine = false;
  p.fine_below_radius_px = 0.0;
  p.k_values = fine_k_values;
  p.max_radius_px = std::min(max_radius_px, kFineOverlap * fine_below_radius_px);
  p.isolate_arc = isolate_arc && fine_isolate_arc;
  if (fine_give_up) {
    p.refine_params.give_up_below = std::max(p.refine_params.give_up_below, min_score);
    p.rescue_weak_from = 1.0;  // what gives up below min_score cannot be rescued to it
  }
  if (fine_max_peaks_examined > 0) {
    p.max_peaks_examined = fine_max_peaks_examined;
    p.max_circles = std::min(max_circles, fine_max_peaks_examined);
  }
  if (fine_stop_after_missed_peaks > 0) p.stop_after_missed_peaks = fine_stop_after_missed_peaks;
  return p;
}

PixelToPixelParams PixelToPixelParams::large_circle_search() const {
  PixelToPixelParams p = *this;
  p.fine_below_radius_px = 0.0;
  p.min_radius_px = std::max(min_radius_px, fine_below_radius_px);
  return p;
}

std::vector<Circle> PixelToPixelDetector::detect_multi_scale(const cv::Mat& image) {
  start(std::nullopt);
  edges_ready_ = false;  // neither search leaves its map here: redetect finds nothing
  orientation_ready_ = false;
  if (!small_) {
    small_ = std::make_unique<PixelToPixelDetector>(params_.small_circle_search());
    large_ = std::make_unique<PixelToPixelDetector>(params_.large_circle_search());
  }
  std::vector<Circle> found = small_->detect(image);
  // Every radius is small: nothing is left for the halved image.
  if (params_.fine_below_radius_px >= params_.max_radius_px) {
    diag_ = small_->diag_;
    return found;
  }
  // fine_shared_edges: the small search's whole-image map (its edges_) is the full-resolution
  // map the large search's candidates are refined on (detect() came here only for an image
  // large enough to halve, as large_->detect would).
  const bool share = params_.fine_shared_edges && small_->edges_ready_;
  const std::vector<Circle> large =
      share ? large_->detect_coarse_to_fine(image, &small_->edges_) : large_->detect(image);
  found.insert(found.end(), large.begin(), large.end());
  diag_ = small_->diag_;  // the full-resolution edges and votes
  return keep_best_separated(std::move(found));
}

}  // namespace stereoball::ball_detector
