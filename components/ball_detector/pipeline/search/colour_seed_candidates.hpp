#pragma once
// Left circles refined from colour-region seeds (core/colour_seeds.hpp): a ball whose outline
// the whole frame's votes missed, found from its colour blob instead.

#include "ball_detector/pipeline/search/search_strategy.hpp"
#include "ball_detector/pipeline/search/search_tools.hpp"

namespace stereoball::ball_detector {

/// The colour seeds of the whole rectified left eye (tools.rect_left, after the whole-frame
/// votes) refined by the left detector, as outcome.left (no pairing); keeps the seeds in
/// scratch.colour_seeds. nullopt unless params.colour_seeds.enabled and a BGR image.
class ColourSeedCandidates : public SearchStrategy {
 public:
  std::optional<SearchOutcome> run(const FrameState& frame, FrameScratch& scratch,
                                   SearchTools& tools) const override;
  /// The seeds run() refines: tools.rect_left's colour blobs over the left detector's configured
  /// radii; reads only those (may run beside the left detector's edge step); nullopt as run().
  static std::optional<std::vector<Circle>> blob_seeds(const SearchTools& tools);
  /// run() with its seeds found already (blob_seeds() of this frame).
  static SearchOutcome refine(std::vector<Circle> seeds, FrameScratch& scratch, SearchTools& tools);
};

/// known plus each of found that lies apart from every circle kept so far (centres closer than
/// half the larger radius are one circle), in found's order.
void add_unknown_circles(const std::vector<Circle>& found, std::vector<Circle>& known);

}  // namespace stereoball::ball_detector
