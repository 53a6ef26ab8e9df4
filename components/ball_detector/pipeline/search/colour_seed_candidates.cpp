#include "ball_detector/pipeline/search/colour_seed_candidates.hpp"

#include <algorithm>
#include <cmath>

#include "ball_detector/core/colour_seeds.hpp"

namespace stereoball::ball_detector {

std::optional<SearchOutcome> ColourSeedCandidates::run(const FrameState&, FrameScratch& scratch,
                                                       SearchTools& tools) const {
  std::optional<std::vector<Circle>> seeds = blob_seeds(tools);
  if (!seeds) return std::nullopt;
  return refine(std::move(*seeds), scratch, tools);
}

std::optional<std::vector<Circle>> ColourSeedCandidates::blob_seeds(const SearchTools& tools) {
  if (!tools.params.colour_seeds.enabled || tools.rect_left.type() != CV_8UC3) return std::nullopt;
  // The configured radii: the range the whole left eye's votes search (radius_range() once
  // they are cast), read without touching what the edge step beside this may write.
  const PixelToPixelParams& p2p = tools.left_detector.params();
  return colour_blob_seeds(tools.rect_left, p2p.min_radius_px, p2p.max_radius_px,
                           tools.params.colour_seeds);
}

SearchOutcome ColourSeedCandidates::refine(std::vector<Circle> seeds, FrameScratch& scratch,
                                           SearchTools& tools) {
  scratch.colour_seeds = std::move(seeds);
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
