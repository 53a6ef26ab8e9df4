#pragma once
// The image measures of `stereoball doctor` on live pairs: exposure and blur per eye, the sign
// of disparity of matched features (eye order) and the rectified row error. Pure: images in,
// figures out (OpenCV, no DDS, no I/O).

#include <opencv2/core.hpp>

#include <cstddef>

#include "doctor_checks.hpp"
#include "stereo/core/rectifier.hpp"

namespace stereoball::doctor {

/// Mean grey level, clipped shares and variance of the Laplacian of one image (grey or BGR).
EyeImageStats measure_eye(const cv::Mat& image);

/// Parameters of the disparity sign count.
struct SignParams {
  int max_features = 1000;  ///< ORB features per eye
  /// A match counts when its rectified rows differ by at most this. Loose on purpose: a
  /// swapped pair goes through the other camera's model and its rows land up to ~20 px apart
  /// (OpenCV's chessboard rig), yet its disparities are still negative; the sign decides.
  double max_row_diff_px = 20.0;
  double min_abs_disparity_px = 1.0;  ///< matches closer than this in x (far away) say nothing
};

/// Row-consistent ORB matches (cross-checked) of two rectified images by the sign of
/// x_left - x_right: {positive, negative}.
std::pair<std::size_t, std::size_t> disparity_signs(const cv::Mat& left_rect,
                                                    const cv::Mat& right_rect,
                                                    const SignParams& params = {});

/// Adds one live pair to m: exposure and blur of both eyes always; with a rectifier (the live
/// calibration; images of its size) the disparity signs and the row residuals of the
/// project's row check (stereo/core/row_check.hpp) after rectification. rectified: the
/// source already rectified the images.
void add_pair(StereoMeasures& m, const stereo::Rectifier* rectifier, const cv::Mat& left,
              const cv::Mat& right, bool rectified, const SignParams& params = {});

}  // namespace stereoball::doctor
