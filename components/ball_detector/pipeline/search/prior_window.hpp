#pragma once
// The searches near a track's prior start from the left box around where the track expects the
// ball; the prior-window search votes in that box and searches the right eye in its circles'
// partner boxes.

#include "ball_detector/pipeline/search/predicted_partner.hpp"
#include "ball_detector/pipeline/search/search_strategy.hpp"
#include "ball_detector/pipeline/search/search_tools.hpp"

namespace stereoball::ball_detector {

/// Sets scratch.prior_box and prior_hints and rectifies the box into tools.rect_left (the rest
/// zero); false (nothing done) when the box is smaller than 8x8 px. Needs frame.prior.
bool prepare_prior_box(const FrameState& frame, FrameScratch& scratch, SearchTools& tools);

/// Voting in scratch.prior_box with the last whole frame's thresholds (prepare_prior_box first);
/// its outcome whether or not it pairs (kPriorWindow).
class PriorWindowSearch : public SearchStrategy {
 public:
  std::optional<SearchOutcome> run(const FrameState& frame, FrameScratch& scratch,
                                   SearchTools& tools) const override;

 private:
  PredictedPartner pairing_;
};

}  // namespace stereoball::ball_detector
