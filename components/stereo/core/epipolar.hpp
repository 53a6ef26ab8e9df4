#pragma once
// Epipolar check of paper section II: in rectified images the centres of one
// ball lie on the same row; pairs further apart than a tolerance are rejected
// and the accepted pair gets the average of the two rows.

#include <opencv2/core.hpp>

#include <optional>
#include <string>
#include <vector>

#include "common/util/result.hpp"

namespace stereoball::stereo {

/// Parameters of the epipolar row check.
struct EpipolarParams {
  double max_row_diff_px = 2.0;  ///< largest accepted |y_left - y_right|, rectified pixels
  /// Success, or an error naming the bad field and its allowed range.
  Status validate() const;
};

/// Outcome of checking one left/right pair of rectified centres.
struct EpipolarMatch {
  bool accepted = false;       ///< row difference within tolerance
  double row_residual_px = 0;  ///< |y_left - y_right|, rectified pixels
  double row_px = 0;           ///< averaged row (y_left + y_right) / 2, rectified pixels
  double x_left_px = 0;        ///< left column, rectified pixels
  double x_right_px = 0;       ///< right column, rectified pixels
};

/// Index pair of the best match between candidate lists (see EpipolarCheck::best_pair).
struct CandidatePair {
  std::size_t left_index = 0;   ///< index into the left candidates
  std::size_t right_index = 0;  ///< index into the right candidates
  EpipolarMatch match;          ///< the accepted match
};

/// Applies the row tolerance to rectified centre pairs.
class EpipolarCheck {
 public:
  /// params must pass validate().
  explicit EpipolarCheck(const EpipolarParams& params);

  /// Checks one pair of rectified centres, pixels.
  EpipolarMatch check(cv::Point2d left_px, cv::Point2d right_px) const;

  /// Among all accepted pairs with non-negative disparity, the one with the smallest
  /// row residual; nullopt if none is accepted.
  std::optional<CandidatePair> best_pair(const std::vector<cv::Point2d>& left_px,
                                         const std::vector<cv::Point2d>& right_px) const;

  const EpipolarParams& params() const { return params_; }

 private:
  EpipolarParams params_;
};

}  // namespace stereoball::stereo
