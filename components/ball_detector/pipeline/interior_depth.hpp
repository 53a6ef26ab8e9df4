#pragma once
// Addition beyond the paper: a ball is a solid, so whatever texture shows inside its outline is
// at the ball's own depth. Dense texture (carpet, gravel) forms circles of every size, and the
// other eye's texture holds a circle of the right size at almost any disparity, so a chance
// pair can pass the epipolar, size and floor checks. The texture inside such a circle still
// lies on the surface it belongs to: matched between the eyes it gives that surface's
// disparity, not the outline's. A plain ball has no interior texture and is left alone.
// Pure: rectified images in, a verdict out.

#include "ball_detector/core/circle.hpp"

#include <opencv2/core.hpp>

namespace stereoball::ball_detector {

/// Settings of the interior depth check.
struct InteriorDepthParams {
  bool enabled = true;
  /// Sampled interior whose grey-level standard deviation is below this holds nothing to
  /// match: the pair stands. Grey levels (0-255).
  double min_texture = 6.0;
  /// The best match elsewhere must reach this normalised cross-correlation to count, [0, 1].
  double min_match = 0.6;
  /// ... and beat the best match at the ball's own disparities by this much.
  double min_margin = 0.25;
};

/// Horizontal image shifts (x_left - x_right, rectified pixels) of interest for one pair.
struct ShiftWindow {
  double ball_lo_px = 0.0;  ///< the ball's outline (its centre's depth)
  double ball_hi_px = 0.0;  ///< the ball's nearest surface (centre depth - radius)
  double search_lo_px = 0.0;
  double search_hi_px = 0.0;
};

/// What matching the interior of a left circle along its rows in the right eye found.
struct InteriorDepth {
  bool textured = false;       ///< at least 3 rows had texture to match (else no verdict)
  int rows_textured = 0;       ///< sampled rows with texture
  int rows_elsewhere = 0;      ///< of those, rows matching clearly better off the ball's shifts
  double best_shift_px = 0.0;  ///< median of those rows' best shifts (0 if none)
  double best_match = 0.0;     ///< that row's normalised cross-correlation there
  double ball_match = 0.0;     ///< that row's best within the ball's shifts
  bool contradicts = false;    ///< most textured rows lie clearly at another depth
};

/// The left rectified pixels the check reads: up to 12 rows evenly over the disc of 0.8 r inside
/// circle, each its chord, clipped to an image of size, one row of margin above and below
/// (bounding box). Empty if nothing of the inside is in the image.
cv::Rect interior_rows_region(const Circle& circle, cv::Size size);

/// The right rectified pixels the check reads for window (the region's columns moved by every
/// searched shift), clipped to size.
cv::Rect interior_search_region(const cv::Rect& left_region, const ShiftWindow& window,
                                cv::Size size);

/// cv::matchTemplate(image, templ, result, TM_CCOEFF_NORMED) for a one-row 8-bit template
/// (1 or 3 channels, as image): summed directly when that is small, which skips OpenCV's DFT
/// set-up; flat windows give 0.
void row_template_correlation(const cv::Mat& image, const cv::Mat& templ, cv::Mat& result);

/// Matches each of up to 12 rows (chords of the 0.8 r disc) of the interior of circle (left) along
/// the same row of right
/// (+-1 row) at every whole shift of window's search range, by normalised cross-correlation;
/// contradicts when more than half of the textured rows (at least 3) match clearly better off
/// the ball's shifts. left and right: rectified 8-bit images of one type (1 or 3 channels),
/// valid at least over interior_rows_region and interior_search_region.
InteriorDepth interior_depth(const cv::Mat& left, const cv::Mat& right, const Circle& circle,
                             const ShiftWindow& window, const InteriorDepthParams& params);

}  // namespace stereoball::ball_detector
