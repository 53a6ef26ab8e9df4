#pragma once
// The last resort for a hue-only rim (a ball that differs from the floor in hue, hardly in
// brightness, on a floor whose brightness texture sets the frame's edge thresholds): seeds
// refined on the left image with its brightness removed, each found circle's right outline
// looked for the same way, and the pairs checked as any are (edge_map.hpp,
// compute_brightness_free_edge_map). Nothing for grey input.

#include <span>

#include "ball_detector/pipeline/search/search_strategy.hpp"
#include "ball_detector/pipeline/search/search_tools.hpp"

namespace stereoball::ball_detector {

/// Which seeds the brightness-free search starts from.
enum class BrightnessFreeSeeds {
  kColourSeeds,      ///< the whole-frame search's colour seeds (scratch.colour_seeds)
  kExpectedOutline,  ///< the prior's expected left outline
};

/// The brightness-free search from its seeds (kBrightnessFree); nullopt unless
/// params.colour_seeds.chroma_outlines and there are seeds. Its outcome whether or not it pairs.
class BrightnessFreeSearch : public SearchStrategy {
 public:
  /// seeds: where the search starts.
  explicit BrightnessFreeSearch(BrightnessFreeSeeds seeds) : seeds_(seeds) {}
  std::optional<SearchOutcome> run(const FrameState& frame, FrameScratch& scratch,
                                   SearchTools& tools) const override;

 private:
  /// seeds (left rectified px) searched and paired.
  SearchOutcome pair_seeds(const FrameState& frame, SearchTools& tools,
                           std::span<const Circle> seeds) const;
  /// The right outline of left's ball along its epipolar line, scored on the right partner box
  /// with its brightness removed (edges at thresholds, the left box's).
  std::optional<Circle> right_outline(const FrameState& frame, SearchTools& tools,
                                      const Circle& left, const EdgeThresholds& thresholds) const;

  BrightnessFreeSeeds seeds_;
};

}  // namespace stereoball::ball_detector
