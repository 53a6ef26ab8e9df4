#include "ball_detector/pipeline/search/coarse_search.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <span>

#include "ball_detector/pipeline/search/radius_bands.hpp"
#include "ball_detector/pipeline/search/search_tools.hpp"

namespace stereoball::ball_detector {

void CoarseSearch::set_up(const BallDetectorParams& p, int image_width_px,
                          const std::optional<stereo::PinholeCamera>& left_camera) {
  level = coarse_level(image_width_px, p.coarse_to_fine);
  // A frame not wider than the target is halved once: the reduced eye takes the radii it
  // resolves; the smaller ones, cheap at full width, are the full-width radius bands'.
  by_radius = level == 0 && p.coarse_by_radius && p.coarse_to_fine.target_width_px > 0;
  if (by_radius) level = 1;
  detector.reset();
  fine_path.reset();
  if (level == 0) return;
  const PixelToPixelParams full = p.detector_params();
  split = split_radius_range({full.min_radius_px, full.max_radius_px}, level,
                             p.coarse_to_fine.min_coarse_radius_px);
  if (!holds_radii(split.coarse_px) || split.coarse_px.max_px <= split.coarse_px.min_px) {
    level = 0;  // nothing is large enough for the reduced eye
    by_radius = false;
    return;
  }
  params = params_at_level(full, level);
  params.min_radius_px = split.coarse_px.min_px;
  // The smoothing box covers the same scene as at full width (k and the radii are divided
  // alike): a full-size box on the reduced votes sums four times the area of the long lines of
  // large radii that pile up over clutter, and those sums outrank a ball's own peak.
  params.box_size_px = std::max(3, (full.box_size_px >> level) | 1);
  params.max_peaks_examined = std::min(params.max_peaks_examined, kCoarsePeaksExamined);
  detector.emplace(params);
  band_detectors.clear();
  // As the single-image coarse search (PixelToPixelParams::coarse_to_fine): on the reduced eye
  // small round texture outvotes a ball's outline unless peaks need voters from around them.
  detector->set_reduced_image_options(full.coarse_min_voted_coverage, true);
  if (!by_radius && holds_radii(split.fine_px) && split.fine_px.max_px > split.fine_px.min_px) {
    fine_path.emplace(full);
    fine_path->set_camera(p.perspective_outline ? left_camera : std::nullopt);
  }
}

bool cast_reduced_left_votes(SearchTools& tools) {
  CoarseSearch& coarse = tools.coarse;
  // The full-resolution edges (and so the thresholds the right eye's boxes and the searches near
  // a prior use) as the full search makes them; only the voting runs on the reduced eye. The two
  // read only the rectified eye and write each its own detector: with tasks at once the edge
  // step runs beside the reduced eye's votes (before, a wide frame's first third on one core).
  bool edges = false, votes = false;
  tools.run_tasks(2, [&](int task) {
    if (task == 0) {
      edges = tools.left_detector.find_edges(tools.rect_left);
      return;
    }
    reduce_image(tools.rect_left, coarse.level, coarse.reduced_left);
    votes = coarse.detector->cast_votes(coarse.reduced_left);
  });
  return edges && votes;
}

bool cast_halved_left_votes(SearchTools& tools) {
  CoarseSearch& coarse = tools.coarse;
  // The eye is halved once: its edges are the full-width ones halved (a faint outline the
  // full-width edge step keeps is lost to an edge step on the halved eye, and it costs less).
  reduce_image(tools.rect_left, coarse.level, coarse.reduced_left);
  halve_edge_map(tools.left_detector.edge_map(), coarse.reduced_left, coarse.params.edge.thin,
                 coarse.halved_edges);
  return coarse.detector->cast_votes_on_edges(coarse.halved_edges, tools.left_vote_tasks());
}

bool cast_full_width_lines(SearchTools& tools) {
  // Rays only over the fine path's radii (a few pixels each, nothing asks for their peaks): the
  // lines are what the bands replay. An empty fine range plots the whole range, as before.
  const RadiusSplit& split = tools.coarse.split;
  const SearchHints hints{holds_radii(split.fine_px) ? split.fine_px : RadiusRange{0.0, 1e9}};
  if (!tools.left_detector.cast_votes_on_last_edges(hints, tools.left_vote_tasks())) return false;
  tools.left_detector.forget_hints();  // the reduced eye's circles are refined on it
  return true;
}

namespace {

// The reduced eye's circles in radius bands (README: radius bands), each band on the lines the
// whole range's votes were cast along (redetect_from: no window rules again), best first per
// band, at most kCoarseBandCircles of each.
void add_reduced_band_circles(SearchTools& tools, const TaskRunner& run, double min_separation_px,
                              double min_voted_coverage, std::vector<Circle>& out) {
  CoarseSearch& coarse = tools.coarse;
  const std::vector<SearchHints> bands = radius_bands(
      coarse.params.min_radius_px, coarse.params.max_radius_px, coarse.reduced_left.rows);
  while (coarse.band_detectors.size() < bands.size()) {
    PixelToPixelParams band_params = coarse.params;
    band_params.max_peaks_examined = static_cast<int>(kCoarseBandCircles);
    coarse.band_detectors.emplace_back(band_params);
    coarse.band_detectors.back().set_reduced_image_options(min_voted_coverage, true);
  }
  // Each band replays the whole range's lines into its own detector: the bands are tasks, their
  // circles joined in band order as one band after the other gives them.
  std::vector<std::vector<Circle>> per_band(bands.size());
  run(static_cast<int>(bands.size()), [&](int i) {
    const auto b = static_cast<std::size_t>(i);
    per_band[b] = coarse.band_detectors[b].redetect_from(*coarse.detector, bands[b]);
    if (per_band[b].size() > kCoarseBandCircles) per_band[b].resize(kCoarseBandCircles);
  });
  for (const std::vector<Circle>& found : per_band)
    out.insert(out.end(), found.begin(), found.end());
  std::stable_sort(out.begin(), out.end(),
                   [](const Circle& a, const Circle& b) { return a.score > b.score; });
  // One place and size found by several bands (or the whole range) is refined once.
  out = best_of_each_place(out, min_separation_px);
}

}  // namespace

CoarseLeftCircles::CoarseLeftCircles(SearchTools& tools)
    : CoarseLeftCircles(tools, tools.run_tasks) {}

const std::vector<Circle>& CoarseLeftCircles::whole_reduced() {
  if (whole_) return *whole_;
  // Each peak refined as a task (circles_of_votes() in parts: the same circles).
  PixelToPixelDetector& reduced = *tools_.coarse.detector;
  std::vector<PeakCircles> per_peak(static_cast<std::size_t>(reduced.find_peaks_of_votes()));
  run_(static_cast<int>(per_peak.size()),
       [&](int i) { per_peak[static_cast<std::size_t>(i)] = reduced.refine_peak(i); });
  whole_ = reduced.select_circles(per_peak);
  return *whole_;
}

std::vector<Circle> CoarseLeftCircles::whole_range() {
  return refined_with_fine_path(whole_reduced());
}

std::vector<Circle> CoarseLeftCircles::with_bands() {
  std::vector<Circle> reduced = whole_reduced();
  // In clutter the whole range's strongest peaks are the long lines of large radii crossing
  // there (the reason for the full-width radius bands); on the reduced eye the bands cost a
  // replay of its lines.
  add_reduced_band_circles(tools_, run_, tools_.coarse.params.min_separation_px,
                           tools_.params.detector_params().coarse_min_voted_coverage, reduced);
  return refined_with_fine_path(reduced);
}

std::vector<Circle> CoarseLeftCircles::refined_with_fine_path(const std::vector<Circle>& reduced) {
  CoarseSearch& coarse = tools_.coarse;
  // One at a time and ranked afterwards, as refine_coarse_circles ranks them all at once: the
  // same circles as one call over reduced, whichever of them were refined before.
  refine_new(reduced);
  std::vector<Circle> held;
  for (const Circle& c : reduced) {
    const auto it = std::find_if(refined_.begin(), refined_.end(),
                                 [&](const auto& done) { return done.first == c; });
    held.insert(held.end(), it->second.begin(), it->second.end());
  }
  std::vector<Circle> found = tools_.left_detector.keep_best_separated(std::move(held));
  if (coarse.fine_path) {
    found.insert(found.end(), fine_->begin(), fine_->end());
    std::stable_sort(found.begin(), found.end(),
                     [](const Circle& a, const Circle& b) { return a.score > b.score; });
  }
  const auto most = static_cast<std::size_t>(tools_.params.max_candidates_per_eye);
  if (found.size() > most) found.resize(most);
  return found;
}

void CoarseLeftCircles::refine_new(const std::vector<Circle>& reduced) {
  // The circles not refined before (each once) and, the first time, the fine path's search: each
  // reads the left detector's full-resolution edges and writes only its own result, so they are
  // tasks, kept in reduced's order as one after the other keeps them.
  std::vector<Circle> fresh;
  for (const Circle& c : reduced) {
    const auto same = [&](const Circle& done) { return done == c; };
    const bool known = std::any_of(refined_.begin(), refined_.end(),
                                   [&](const auto& done) { return same(done.first); });
    if (!known && std::none_of(fresh.begin(), fresh.end(), same)) fresh.push_back(c);
  }
  CoarseSearch& coarse = tools_.coarse;
  const bool fine_due = coarse.fine_path && !fine_;
  std::vector<std::vector<Circle>> results(fresh.size());
  std::vector<Circle> fine;
  run_(static_cast<int>(fresh.size()) + (fine_due ? 1 : 0), [&](int task) {
    const auto i = static_cast<std::size_t>(task);
    if (i == fresh.size()) {
      const EdgeThresholds thresholds = thresholds_of(tools_.left_detector.edge_map());
      fine =
          coarse.fine_path->detect(tools_.rect_left, thresholds, SearchHints{coarse.split.fine_px});
      return;
    }
    results[i] = refine_coarse_circles(tools_.left_detector, std::span<const Circle>(&fresh[i], 1),
                                       coarse.level, tools_.params.coarse_to_fine.max_refine_shift);
  });
  for (std::size_t i = 0; i < fresh.size(); ++i)
    refined_.emplace_back(fresh[i], std::move(results[i]));
  if (fine_due) fine_ = std::move(fine);
}

std::vector<Circle> coarse_left_circles(SearchTools& tools) {
  return CoarseLeftCircles(tools).with_bands();
}

}  // namespace stereoball::ball_detector
