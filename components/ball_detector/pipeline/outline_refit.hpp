#pragma once
// Addition beyond the paper: a found pair's outlines fitted again, in both eyes, to the edge
// arcs that agree (core/circle_fit.hpp robust_outline). A ball held in hands has its outline
// partly hidden by fingers and crossed by its seams; the voting and the local refinement can
// settle on a circle that mixes the outline with a seam arc or a finger's edge, off by a fifth
// of the radius in one eye only, and the disparity of such a pair comes from two different
// outlines. Pure settings and the verdict on a refitted pair.

#include "ball_detector/core/circle_fit.hpp"
#include "ball_detector/pipeline/pairing.hpp"

#include <optional>
#include <string>

namespace stereoball::ball_detector {

/// Settings of the robust refit of a found pair's outlines.
struct OutlineRefitParams {
  /// Off by default: on the simulated worlds it costs the colour-seed, band and radius-balance
  /// searches found balls (their tests); on the real held-ball pairs it removes wrong pairs.
  bool enabled = false;
  OutlineSearchParams search;  ///< the refit in each eye
  /// A pair whose refitted outlines no longer pair (rows, size) is withdrawn: the two eyes'
  /// circles were not one sphere's outline. false = the pair stands as first found.
  bool withdraw_unpaired = true;
};

/// Addition: the outline the other eye sees of the ball behind seen (an outline in the right
/// eye when seen_right, else the left) had the ball not moved between the two exposures: the
/// ball at the depth seen's size gives, on seen's line of sight. nullopt if seen is no outline
/// of a ball in front of both cameras.
std::optional<Circle> unmoved_partner_outline(const PairingContext& ctx, const Circle& seen,
                                              bool seen_right);

/// Addition: whether the two eyes' outline radii of a pair that needs the motion allowance
/// (PairingContext::motion_radii) can belong to one ball. Between the exposures its depth
/// changes by at most the motion (motion_radii ball radii), its outline radius by that over
/// its depth (the nearer of the triangulated and the size's); the fits err by the epipolar
/// tolerance. The left radius is compared as the right eye would see it.
struct MovedRadii {
  bool agree = true;
  double difference_px = 0.0;  ///< |left as the right sees it - right|, pixels
  double allowed_px = 0.0;
};
MovedRadii moved_radii(const PairingContext& ctx, const StereoPair& pair);

/// What refitting a found pair's outlines gave.
struct RefitVerdict {
  bool changed = false;            ///< at least one eye's circle moved
  std::optional<StereoPair> pair;  ///< the refitted pair (changed), nullopt if it does not pair
  std::string note;                ///< for the detection's reason
};

/// The verdict on left/right refitted from found_left/found_right: unchanged when neither eye
/// moved; else the pair the refits make (evaluate_pair) if it is size-consistent and on the
/// floor, nullopt otherwise.
RefitVerdict judge_refit(const PairingContext& ctx, const Circle& found_left,
                         const Circle& found_right, const Circle& left, const Circle& right);

}  // namespace stereoball::ball_detector
