#pragma once
// How well one chessboard pair agrees with a stereo calibration: the board pose is fitted to
// both eyes at once (the right eye sees it through R, T), so a pair whose right view was taken
// a moment after the left one (the board moved) cannot be explained and keeps a large error.

#include "stereo/core/calibration.hpp"

#include <opencv2/core.hpp>

#include <vector>

namespace stereoball::stereo {

/// Reprojection error of one pair under a fixed calibration.
struct PairError {
  double rms_px = 0.0;             ///< RMS over both eyes' corners after the joint pose fit, pixels
  double left_rms_px = 0.0;        ///< left corners alone, pixels
  double right_rms_px = 0.0;       ///< right corners alone, pixels
  double mean_row_error_px = 0.0;  ///< mean |y_left - y_right| after rectification, pixels
};

/// Fits one board pose (6 dof, left camera frame) to the left and right corners of a pair
/// under calib (intrinsics, distortion, R, T fixed) and returns the remaining errors.
/// board_m: the board's corners in its own frame (metres), same order as the image corners.
PairError stereo_pair_error(const StereoCalibration& calib, const std::vector<cv::Point3f>& board_m,
                            const std::vector<cv::Point2f>& left_px,
                            const std::vector<cv::Point2f>& right_px);

}  // namespace stereoball::stereo
