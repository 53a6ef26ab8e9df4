#pragma once
// The first search near a track's prior: the outlines the prior predicts in each eye refined
// where they are (no voting); it counts only when it pairs within the prior's gate.

#include "ball_detector/pipeline/search/predicted_partner.hpp"
#include "ball_detector/pipeline/search/search_strategy.hpp"
#include "ball_detector/pipeline/search/search_tools.hpp"

namespace stereoball::ball_detector {

/// The prior's expected outlines refined (left in scratch.prior_box, prepare_prior_box first);
/// nullopt unless params.prior_seeded and a pair within the gate (kExpectedOutlines).
class ExpectedOutlinesSearch : public SearchStrategy {
 public:
  std::optional<SearchOutcome> run(const FrameState& frame, FrameScratch& scratch,
                                   SearchTools& tools) const override;

 private:
  PredictedPartner pairing_;
};

}  // namespace stereoball::ball_detector
