#include "ball_detector/pipeline/search/whole_frame.hpp"

#include <algorithm>
#include <atomic>
#include <optional>

#include "ball_detector/pipeline/search/radius_bands.hpp"

namespace stereoball::ball_detector {

std::optional<SearchOutcome> WholeFrameSearch::run(const FrameState& frame, FrameScratch& scratch,
                                                   SearchTools& tools) const {
  // Nothing else can start before the left eye is rectified: its rows are shared out.
  tools.rectify_whole_in_tasks(frame.left_channel, stereo::Eye::kLeft, frame.rectified,
                               tools.rect_left);
  if (tools.coarse.by_radius) return by_radius(frame, scratch, tools);
  bool edges_made = false;  // the left detector holds rect_left's full-resolution edges
  if (tools.coarse.on()) {
    // The reduced eye's votes first: where they pair, the frame costs a fraction of the full
    // search. A ball they do not resolve (an outline partly hidden by hands whose edges merge
    // with it at half size) is then searched for exactly as without coarse to fine; so is one
    // only the colour seeds would find (their circle may lose there to a better voted one).
    edges_made = cast_reduced_left_votes(tools);
    if (edges_made) {
      if (std::optional<SearchOutcome> coarse = coarse_try(frame, scratch, tools)) return coarse;
    }
  }
  std::optional<std::vector<Circle>> blobs;  // the colour seeds' blobs, when found early
  const bool voted = cast_full_width_votes(tools, edges_made, &blobs);
  // Task 0 finishes the search (peaks, right eye, pairing). When a band search is due, the
  // other task searches the left eye's radius bands on the same votes meanwhile, in case it
  // pairs nothing: on another core this takes the bands out of the frame's time, and the work
  // is dropped (stopped between bands) if it pairs. Run in turn, task 0 goes first and the
  // bands run only if it paired nothing. Task 0 does not touch what the band task reads (the
  // left detector's edges and lines), nor it anything task 0 touches.
  const bool bands_due = scratch.bands_due;
  if (bands_due && tools.task_threads > 1) {
    SearchOutcome out = pair_beside_bands(frame, scratch, tools, voted, std::move(blobs));
    out.path = SearchPath::kWholeFrame;
    return out;
  }
  SearchOutcome out;
  std::atomic<bool> paired{false};
  std::vector<Circle> bands;
  tools.run_tasks(bands_due ? 2 : 1, [&](int task) {
    if (task == 1) {
      if (paired) return;
      tools.observe(SearchPath::kRadiusBands, true);
      bands = detect_left_in_bands(tools, &paired, scratch.band);
      tools.observe(SearchPath::kRadiusBands, false);
      return;
    }
    out = pair_left_circles(frame, scratch, tools,
                            voted ? circles_of_votes(tools, !bands_due) : std::vector<Circle>{},
                            voted, std::move(blobs));
    paired = out.found();
  });
  if (bands_due && !paired) scratch.band_left = std::move(bands);
  out.path = SearchPath::kWholeFrame;
  return out;
}

SearchOutcome WholeFrameSearch::by_radius(const FrameState& frame, FrameScratch& scratch,
                                          SearchTools& tools) const {
  SearchOutcome out;
  out.path = SearchPath::kWholeFrame;
  const bool bands_due = scratch.bands_due;
  std::optional<std::vector<Circle>> blobs;  // the colour seeds' blobs, when found early
  // The full-width lines only when the bands may replay them: their window rules are the
  // largest part of the votes, and the reduced eye's whole range does without them.
  if (!full_width_edges(tools, &blobs) || !cast_halved_left_votes(tools) ||
      (bands_due && !cast_full_width_lines(tools))) {
    if (bands_due) scratch.band_left.emplace();  // an invalid image: nothing to search
    return out;
  }
  if (bands_due && tools.task_threads > 1) {
    out = by_radius_beside_bands(frame, scratch, tools, std::move(blobs));
    out.path = SearchPath::kWholeFrame;
    return out;
  }
  std::vector<Circle> whole = CoarseLeftCircles(tools).whole_range();
  // As the full-width search: task 0 pairs (with the colour seeds), the other task searches the
  // due radius bands on the full-width lines meanwhile, dropped once task 0 pairs.
  std::atomic<bool> paired{false};
  std::vector<Circle> bands;
  tools.run_tasks(bands_due ? 2 : 1, [&](int task) {
    if (task == 1) {
      if (paired) return;
      tools.observe(SearchPath::kRadiusBands, true);
      bands = detect_left_in_bands(tools, &paired, scratch.band);
      tools.observe(SearchPath::kRadiusBands, false);
      return;
    }
    out = pair_left_circles(frame, scratch, tools, std::move(whole), true, std::move(blobs));
    paired = out.found();
  });
  if (bands_due && !paired) scratch.band_left = std::move(bands);
  out.path = SearchPath::kWholeFrame;
  return out;
}

bool WholeFrameSearch::full_width_edges(SearchTools& tools,
                                        std::optional<std::vector<Circle>>* blobs) {
  if (tools.task_threads <= 1) return tools.left_detector.find_edges(tools.rect_left);
  // As cast_full_width_votes: the colour blobs (read from the rectified eye only) beside the
  // edge step, out of the work that follows.
  bool edges = false;
  tools.run_tasks(2, [&](int task) {
    if (task == 0) {
      edges = tools.left_detector.find_edges(tools.rect_left);
    } else {
      *blobs = ColourSeedCandidates::blob_seeds(tools);
    }
  });
  return edges;
}

SearchOutcome WholeFrameSearch::by_radius_beside_bands(
    const FrameState& frame, FrameScratch& scratch, SearchTools& tools,
    std::optional<std::vector<Circle>> blobs) const {
  // As pair_beside_bands: every band's votes beside the reduced eye's circles (its peaks and
  // their full-width refinement), then the pairing beside the bands' peaks. The reduced eye's
  // task reads the left detector's edges only, as the bands do.
  LeftBandParts bands(tools, scratch.band);
  const int band_count = bands.bands();
  std::vector<Circle> whole;
  tools.run_tasks(band_count + 1, [&](int task) {
    if (task == band_count) {
      whole = CoarseLeftCircles(tools, run_tasks_in_turn).whole_range();
      return;
    }
    tools.observe(SearchPath::kRadiusBands, true);
    bands.vote(task);
    tools.observe(SearchPath::kRadiusBands, false);
  });
  return pair_beside_band_peaks(frame, scratch, tools, bands, std::move(whole), true,
                                std::move(blobs));
}

SearchOutcome WholeFrameSearch::pair_beside_bands(const FrameState& frame, FrameScratch& scratch,
                                                  SearchTools& tools, bool voted,
                                                  std::optional<std::vector<Circle>> blobs) const {
  // As the two tasks in run() do, in parts small enough that both cores end together: in a
  // lost ball's frame the left peaks (most of task 0) outlasted a small band and a large band
  // outlasted them. First every band's votes beside the left peaks' refinement, then the
  // pairing beside the bands' peaks. Each part reads or writes what it did in run()'s tasks.
  LeftBandParts bands(tools, scratch.band);
  const int band_count = bands.bands();
  const int left_peaks = voted ? tools.left_detector.find_peaks_of_votes() : 0;
  std::vector<PeakCircles> per_peak(static_cast<std::size_t>(left_peaks));
  tools.run_tasks(band_count + left_peaks, [&](int task) {
    if (task >= band_count) {
      per_peak[static_cast<std::size_t>(task - band_count)] =
          tools.left_detector.refine_peak(task - band_count);
      return;
    }
    tools.observe(SearchPath::kRadiusBands, true);
    bands.vote(task);
    tools.observe(SearchPath::kRadiusBands, false);
  });
  return pair_beside_band_peaks(
      frame, scratch, tools, bands,
      voted ? tools.left_detector.select_circles(per_peak) : std::vector<Circle>{}, voted,
      std::move(blobs));
}

SearchOutcome WholeFrameSearch::pair_beside_band_peaks(
    const FrameState& frame, FrameScratch& scratch, SearchTools& tools, LeftBandParts& bands,
    std::vector<Circle> left, bool with_colour_seeds,
    std::optional<std::vector<Circle>> blobs) const {
  SearchOutcome out;
  std::atomic<bool> paired{false};
  tools.run_tasks(1 + bands.peaks(), [&](int task) {
    if (task > 0) {
      if (paired) return;  // the bands' circles are not wanted any more
      tools.observe(SearchPath::kRadiusBands, true);
      bands.refine(task - 1);
      tools.observe(SearchPath::kRadiusBands, false);
      return;
    }
    out = pair_left_circles(frame, scratch, tools, std::move(left), with_colour_seeds,
                            std::move(blobs));
    paired = out.found();
  });
  if (!paired) scratch.band_left = bands.circles();
  return out;
}

bool WholeFrameSearch::cast_full_width_votes(SearchTools& tools, bool edges_made,
                                             std::optional<std::vector<Circle>>* blobs) {
  // The coarse try's edges are this image's, made as cast_votes makes them: only the votes are
  // new at full width. With a runner that runs tasks at once, the votes are split over it: they
  // come before anything else can start, and are a third of a lost ball's frame.
  const VoteTasks vote_tasks = tools.left_vote_tasks();
  if (edges_made) return tools.left_detector.cast_votes_on_last_edges(vote_tasks);
  if (tools.task_threads <= 1) return tools.left_detector.cast_votes(tools.rect_left, vote_tasks);
  // The same edges and votes as cast_votes; the colour blobs (read from the rectified eye only)
  // leave the work that follows the votes, where the other core has the bands or nothing.
  bool edges = false;
  tools.run_tasks(2, [&](int task) {
    if (task == 0) {
      edges = tools.left_detector.find_edges(tools.rect_left);
    } else {
      *blobs = ColourSeedCandidates::blob_seeds(tools);
    }
  });
  return edges && tools.left_detector.cast_votes_on_last_edges(vote_tasks);
}

std::optional<SearchOutcome> WholeFrameSearch::coarse_try(const FrameState& frame,
                                                          FrameScratch& scratch,
                                                          SearchTools& tools) const {
  // A weak pair (a fit pulled onto fingers or a seam scores low) is judged by the full-width
  // search instead, which may find the outline itself or withdraw it.
  const auto strong = [&](const SearchOutcome& o) {
    return o.found() && o.pairing.best &&
           o.pairing.best->score >= tools.params.coarse_min_pair_score;
  };
  CoarseLeftCircles circles(tools);
  std::vector<Circle> whole = circles.whole_range();
  SearchOutcome out = pair_left_circles(frame, scratch, tools, whole, false);
  // The radius bands only when the whole range's circles give no strong pair: the bands (each
  // plots every line again, and their circles are refined at full width) were the largest part
  // of the reduced eye's work, and on the real stereo set they changed no answer where the whole
  // range paired.
  if (!strong(out)) {
    std::vector<Circle> banded = circles.with_bands();
    const bool same = std::equal(banded.begin(), banded.end(), whole.begin(), whole.end());
    if (same) return std::nullopt;  // paired as above already
    out = pair_left_circles(frame, scratch, tools, std::move(banded), false);
  }
  if (!strong(out)) return std::nullopt;
  out.path = SearchPath::kWholeFrame;
  return out;
}

SearchOutcome WholeFrameSearch::pair_left_circles(const FrameState& frame, FrameScratch& scratch,
                                                  SearchTools& tools, std::vector<Circle> left,
                                                  bool with_colour_seeds,
                                                  std::optional<std::vector<Circle>> blobs) const {
  if (with_colour_seeds) {
    std::optional<SearchOutcome> seeded =
        blobs ? ColourSeedCandidates::refine(std::move(*blobs), scratch, tools)
              : colour_seeds_.run(frame, scratch, tools);
    if (seeded) add_unknown_circles(seeded->left, left);
  }
  tools.left_thresholds = thresholds_of(tools.left_detector.edge_map());
  std::vector<Circle> right;
  if (tools.params.right_eye_partner_boxes) {
    right = tools.detect_right_in_boxes(frame, left, false);
  } else {
    tools.rectify_whole(frame.right_channel, stereo::Eye::kRight, frame.rectified,
                        tools.rect_right);
    right = tools.right_detector.detect(tools.rect_right);
    tools.right_edges_box = cv::Rect(cv::Point(0, 0), tools.rect_right.size());
  }
  return pairing_.pair(frame, tools, std::move(left), std::move(right), false);
}

std::vector<Circle> WholeFrameSearch::circles_of_votes(SearchTools& tools, bool peaks_at_once) {
  // Refining and scoring the peaks is most of a whole-frame search (~40 %), and each peak is
  // independent. (With tasks at once and the bands due, pair_beside_bands refines them.)
  if (!peaks_at_once) return tools.left_detector.circles_of_votes();
  const int n = tools.left_detector.find_peaks_of_votes();
  std::vector<PeakCircles> per_peak(static_cast<std::size_t>(n));
  tools.run_tasks(n, [&](int i) {
    per_peak[static_cast<std::size_t>(i)] = tools.left_detector.refine_peak(i);
  });
  return tools.left_detector.select_circles(per_peak);
}

}  // namespace stereoball::ball_detector
