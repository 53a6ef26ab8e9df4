#pragma once
// Voting over the whole left eye (plus its colour seeds), the right eye in the left circles'
// partner boxes or whole, and pairing; when scratch.bands_due, the left eye's radius bands are
// searched beside it on the same votes (README: whole frame). Coarse to fine, the reduced left
// eye's votes are tried first, and the full-width search runs only if they pair nothing.

#include "ball_detector/pipeline/search/colour_seed_candidates.hpp"
#include "ball_detector/pipeline/search/predicted_partner.hpp"
#include "ball_detector/pipeline/search/search_strategy.hpp"
#include "ball_detector/pipeline/search/search_tools.hpp"

namespace stereoball::ball_detector {

class LeftBandParts;

/// The whole-frame search: its outcome whether or not it pairs (kWholeFrame); measures
/// tools.left_thresholds again; leaves scratch.band_left (when bands_due and nothing paired)
/// and scratch.colour_seeds. When nothing pairs, the left detector holds the full-width votes.
class WholeFrameSearch : public SearchStrategy {
 public:
  std::optional<SearchOutcome> run(const FrameState& frame, FrameScratch& scratch,
                                   SearchTools& tools) const override;

 private:
  /// The left detector's last votes turned into circles, each peak a task or all in turn.
  static std::vector<Circle> circles_of_votes(SearchTools& tools, bool peaks_at_once);
  /// Coarse to fine by radius (CoarseSearch::by_radius): the reduced eye's whole range paired,
  /// the full-width radius bands beside it when due; no full-width whole-range search.
  SearchOutcome by_radius(const FrameState& frame, FrameScratch& scratch, SearchTools& tools) const;
  /// The left detector's full-width edges (false: an invalid image); with tasks at once, the
  /// colour blob search beside them, its seeds to *blobs.
  static bool full_width_edges(SearchTools& tools, std::optional<std::vector<Circle>>* blobs);
  /// by_radius() with the radius bands due, split for a runner that runs tasks at once (in
  /// turn it gives the same outcome and scratch.band_left).
  SearchOutcome by_radius_beside_bands(const FrameState& frame, FrameScratch& scratch,
                                       SearchTools& tools,
                                       std::optional<std::vector<Circle>> blobs) const;
  /// Coarse to fine, the reduced eye's votes (cast already) paired: the whole radius range's
  /// circles first, the radius bands' too if those give no pair of coarse_min_pair_score;
  /// nullopt when neither does (the full-width search then answers).
  std::optional<SearchOutcome> coarse_try(const FrameState& frame, FrameScratch& scratch,
                                          SearchTools& tools) const;
  /// The whole frame's pairing with the radius bands due beside it, split for a runner that
  /// runs tasks at once (run() in turn gives the same outcome and scratch.band_left).
  /// The pairing of left (plus the colour seeds' circles, with_colour_seeds) beside the bands'
  /// peaks' refinement, each dropped once it pairs; scratch.band_left gets the bands' circles
  /// when nothing paired. The last step of both band splits.
  SearchOutcome pair_beside_band_peaks(const FrameState& frame, FrameScratch& scratch,
                                       SearchTools& tools, LeftBandParts& bands,
                                       std::vector<Circle> left, bool with_colour_seeds,
                                       std::optional<std::vector<Circle>> blobs) const;
  SearchOutcome pair_beside_bands(const FrameState& frame, FrameScratch& scratch,
                                  SearchTools& tools, bool voted,
                                  std::optional<std::vector<Circle>> blobs) const;
  /// The full-width left eye's votes cast (false: an invalid image); with tasks at once and no
  /// edges yet, its edge step runs beside the colour blob search, whose seeds go to *blobs.
  static bool cast_full_width_votes(SearchTools& tools, bool edges_made,
                                    std::optional<std::vector<Circle>>* blobs);
  /// left (and with_colour_seeds, the colour seeds' circles: from blobs when found already)
  /// paired with the right eye searched in their partner boxes (or whole), the left detector's
  /// edge thresholds measured again.
  SearchOutcome pair_left_circles(const FrameState& frame, FrameScratch& scratch,
                                  SearchTools& tools, std::vector<Circle> left,
                                  bool with_colour_seeds,
                                  std::optional<std::vector<Circle>> blobs = std::nullopt) const;

  ColourSeedCandidates colour_seeds_;
  PredictedPartner pairing_;
};

}  // namespace stereoball::ball_detector
