#pragma once
// Addition beyond the paper, for unsynchronised eyes: a ball that moved between the two
// exposures carries what lies inside its outline (its seams and print, the hands holding it)
// with it, so in rectified images the inside's rows differ between the eyes by as much as the
// outline's. Two outline fits pulled alike off the ball (fingers over its rim, its edge cut by
// the image border) make a pair whose size and depth agree, and whose row difference the
// motion allowance accepts; the inside, matched between the eyes, says by how many rows the
// ball really moved. Pure: rectified images in, the measured offset out.

#include "ball_detector/core/circle.hpp"

#include <opencv2/core.hpp>

namespace stereoball::ball_detector {

/// Where the inside of a left circle is found again in the right eye.
struct InteriorOffset {
  bool measured = false;  ///< the inside was in view, textured, and matched clearly
  double dx_px = 0.0;     ///< x_left - x_right of the best match, rectified pixels
  double dy_px = 0.0;     ///< y_left - y_right of the best match, rectified pixels
  double match = 0.0;     ///< its normalised cross-correlation, [-1, 1]
};

/// Settings of the interior offset measurement (texture and match floors as the interior depth
/// check's, InteriorDepthParams; not chosen on any data).
struct InteriorOffsetParams {
  double inner_fraction = 0.5;  ///< the template is the square of this half-side per radius
  double min_texture = 6.0;     ///< grey-level standard deviation below which nothing is matched
  double min_match = 0.6;       ///< the best match must reach this correlation to count
};

/// The square inside left (half-side inner_fraction r), as far as it lies in left_image (at
/// least half of it), matched in right_image over the rows and columns the right circle puts it
/// at, +- dy_reach_px and dx_reach_px, as far as they lie in right_image (both images rectified,
/// same type, 8-bit, 1 or 3 channels). Not measured when too little is in view, the inside is
/// flat, or the best match is weak.
InteriorOffset interior_offset(const cv::Mat& left_image, const cv::Mat& right_image,
                               const Circle& left, const Circle& right, double dx_reach_px,
                               double dy_reach_px, const InteriorOffsetParams& params = {});

}  // namespace stereoball::ball_detector
