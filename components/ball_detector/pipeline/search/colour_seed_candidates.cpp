#include "ball_detector/pipeline/search/colour_seed_candidates.hpp"

#include <algorithm>
#include <cmath>

#include "ball_detector/core/colour_seeds.hpp"

namespace stereoball::ball_detector {

std::optional<SearchOutcome> ColourSeedCandidates::run(const FrameState&, FrameScratch& scratch,
                                                       SearchTools& tools) const {
  if (!tools.params.colour_seeds.enabled || tools.rect_left.type() != CV_8UC3) return std::nullopt;
  const RadiusRange radii = tools.left_detector.radius_range();
  scratch.colour_seeds =
      colour_blob_seeds(tools.rect_left, radii.min_px, radii.max_px, tools.params.colour_seeds);
  SearchOutcome out;
  out.left = tools.left_detector.refine_seeds(scratch.colour_seeds);
  return out;
}

void add_unknown_circles(const std::vector<Circle>& found, std::vector<Circle>& known) {
  for (const Circle& c : found) {
    const bool seen = std::any_of(known.begin(), known.end(), [&](const Circle& k) {
      return std::hypot(k.x_px - c.x_px, k.y_px - c.y_px) <
             0.5 * std::max(k.radius_px, c.radius_px);
    });
    if (!seen) known.push_back(c);
  }
}

}  // namespace stereoball::ball_detector
