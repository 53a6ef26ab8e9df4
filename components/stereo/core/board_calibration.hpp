#pragma once
// Stereo calibration from chessboard views: sub-pixel corner detection,
// per-camera then joint stereo calibration, rectification, quality figures.
// Pure computation on images already in memory; the tool does the file I/O.

#include "common/util/result.hpp"
#include "stereo/core/calibration.hpp"

#include <opencv2/core.hpp>

#include <optional>
#include <string>
#include <vector>

namespace stereoball::stereo {

/// Chessboard geometry and calibration options.
struct BoardCalibrationParams {
  cv::Size inner_corners{9, 6};  ///< inner corners per row and column
  double square_m = 0.025;       ///< chessboard square side, metres (sets the unit of T)
  int min_pairs = 6;             ///< fewest usable pairs; fewer is an error
  int subpix_window_px = 11;     ///< half-size of the cornerSubPix search window is this / 2
  RectifyOptions rectify;        ///< how the rectified views are chosen
  /// A pair is dropped as inconsistent (e.g. the board moved between an unsynchronised left
  /// and right shot) when its stereo error against the calibration of the other pairs exceeds
  /// both outlier_ratio times their median per-pair error and outlier_min_px; one pair at a
  /// time, worst first, never below min_pairs. outlier_ratio = 0 keeps every pair.
  double outlier_ratio = 3.0;
  double outlier_min_px = 0.3;  ///< see outlier_ratio, pixels
  /// Success, or an error naming the bad field and its allowed range.
  Status validate() const;
};

/// Chessboard corners of one stereo pair, pixels, in board order.
struct PairCorners {
  std::string name;                   ///< label for reports (e.g. file names)
  std::vector<cv::Point2f> left_px;   ///< left corners
  std::vector<cv::Point2f> right_px;  ///< right corners
};

/// A pair left out of the calibration, and why.
struct DroppedPair {
  std::string name;           ///< PairCorners::name
  double error_px = 0;        ///< its stereo RMS against the calibration of the pairs kept
  double rest_median_px = 0;  ///< median per-pair RMS of the pairs kept, pixels
  double row_error_px = 0;    ///< its mean rectified |y_l - y_r| under that calibration
  std::string reason;         ///< one line for reports
};

/// Everything a calibration run produces.
struct BoardCalibrationResult {
  StereoCalibration calibration;           ///< rms_px and per_pair_rms_px filled in
  std::vector<std::string> pair_names;     ///< pairs used, same order as per_pair_rms_px
  double left_rms_px = 0;                  ///< left-only calibration RMS, pixels
  double right_rms_px = 0;                 ///< right-only calibration RMS, pixels
  double mean_rectified_row_error_px = 0;  ///< mean |y_l - y_r| of matched corners, pixels
  double max_rectified_row_error_px = 0;   ///< largest |y_l - y_r| of matched corners, pixels
  std::vector<DroppedPair> dropped;        ///< inconsistent pairs left out, in dropping order
  double all_pairs_rms_px = 0;             ///< stereo RMS with every pair (before dropping)
  double all_pairs_mean_row_error_px = 0;  ///< mean row error with every pair, pixels
  double all_pairs_max_row_error_px = 0;   ///< max row error with every pair, pixels
};

/// A board's inner-corner count from "COLSxROWS" (e.g. "9x6"; x or X), each 2-50; nullopt
/// for anything else.
std::optional<cv::Size> parse_board_size(const std::string& text);

/// Finds the inner chessboard corners with sub-pixel refinement in a grey or BGR image;
/// nullopt if the whole board is not found.
std::optional<std::vector<cv::Point2f>> find_board_corners(const cv::Mat& image,
                                                           const BoardCalibrationParams& params);

/// Puts the right corners in the same board order as the left ones (the 180-degree
/// ambiguity of a board); returns true if it had to reverse them.
bool align_corner_order(const std::vector<cv::Point2f>& left_px,
                        std::vector<cv::Point2f>& right_px);

/// The board's corners in its own frame (z = 0), metres, in findChessboardCorners order.
std::vector<cv::Point3f> board_points_m(const BoardCalibrationParams& params);

/// Calibrates the rig from the corners of several pairs of image_size images, dropping the
/// pairs that disagree with the rest (see BoardCalibrationParams::outlier_ratio); the
/// rectified row errors are those of the pairs kept.
Result<BoardCalibrationResult> calibrate_stereo(const std::vector<PairCorners>& pairs,
                                                cv::Size image_size,
                                                const BoardCalibrationParams& params);

/// Each camera calibrated alone should fit its corners to well under a pixel; when one does
/// not (left_rms_px or right_rms_px above limit_px), the error lies in the images, not in the
/// pairing of the eyes: a line naming both figures and the usual causes with their fixes.
std::optional<std::string> single_camera_fit_problem(const BoardCalibrationResult& result,
                                                     double limit_px = 1.0);

/// Mean and max |y_left - y_right| of corresponding raw points after point rectification,
/// pixels; {0, 0} for no points.
std::pair<double, double> rectified_row_error_px(const StereoCalibration& calib,
                                                 const std::vector<PairCorners>& pairs);

}  // namespace stereoball::stereo
