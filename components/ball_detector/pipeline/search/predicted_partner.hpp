#pragma once
// The last step of every voting search: the left circles the followed ball's colour rejects
// dropped, the eyes' candidates paired, and when nothing pairs, each left circle's right
// outline predicted along its epipolar line and scored on the right eye's edges, then paired
// again (pairing.hpp, predicted_partner).

#include <vector>

#include "ball_detector/pipeline/search/search_strategy.hpp"
#include "ball_detector/pipeline/search/search_tools.hpp"

namespace stereoball::ball_detector {

/// Pairs a search's candidates, with predicted right partners when they pair nothing.
class PredictedPartner {
 public:
  /// left and right (rectified px, best first) paired; near_prior: the search is the prior's
  /// (a laxer border rule for the predicted outlines). The outcome's path is left as given.
  SearchOutcome pair(const FrameState& frame, SearchTools& tools, std::vector<Circle> left,
                     std::vector<Circle> right, bool near_prior) const;

  /// The predicted right outlines of left's circles that score (min_inside_fraction of each
  /// in view), on the right detector's last edges where its box covers them.
  std::vector<Circle> partners(const PairingContext& ctx, SearchTools& tools,
                               const std::vector<Circle>& left, double min_inside_fraction) const;
};

}  // namespace stereoball::ball_detector
