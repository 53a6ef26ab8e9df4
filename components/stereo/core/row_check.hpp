#pragma once
// Measures how well a rectified pair is rectified: matches distinctive
// features of the left image in a 2D window of the right image (so the match
// does not assume rectification) and reports the row residuals.

#include <opencv2/core.hpp>

#include <optional>
#include <string>
#include <vector>

#include "common/util/result.hpp"

namespace stereoball::stereo {

/// Parameters of the feature-based row check.
struct RowCheckParams {
  int max_features = 400;         ///< corners taken from the left image
  int half_block_px = 7;          ///< template is (2*half_block_px+1)^2 pixels
  int max_row_search_px = 10;     ///< rows searched above and below, pixels
  int max_disparity_px = 300;     ///< columns searched to the left of x_left, pixels
  double min_score = 0.9;         ///< minimum normalised cross-correlation of a match
  double max_backmatch_px = 1.0;  ///< right->left match must land this close, pixels
  /// Success, or an error naming the bad field and its allowed range.
  Status validate() const;
};

/// One matched feature.
struct RowMatch {
  cv::Point2d left_px;   ///< position in the left image, pixels
  cv::Point2d right_px;  ///< sub-pixel position in the right image, pixels
  double row_residual_px() const { return right_px.y - left_px.y; }  ///< signed, pixels
};

/// Summary of absolute row residuals, pixels.
struct RowResidualStats {
  std::size_t count = 0;      ///< matches
  double mean_abs_px = 0;     ///< mean |dy|
  double median_abs_px = 0;   ///< median |dy|
  double p90_abs_px = 0;      ///< 90th percentile |dy|
  double max_abs_px = 0;      ///< largest |dy|
  double mean_signed_px = 0;  ///< mean dy (systematic vertical offset)
};

/// Matches features between two rectified images (same size, grey or BGR).
std::vector<RowMatch> match_rows(const cv::Mat& left, const cv::Mat& right,
                                 const RowCheckParams& params);

/// Statistics of |row residual| over the matches.
RowResidualStats summarize_rows(const std::vector<RowMatch>& matches);

}  // namespace stereoball::stereo
