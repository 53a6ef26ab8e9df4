#pragma once
// Rectification as in paper section II: perspective correction, lens
// distortion and bilinear interpolation folded into one fixed-point look-up
// table per eye, computed once per calibration and applied to every frame.

#include "common/util/result.hpp"
#include "stereo/core/calibration.hpp"

#include <opencv2/core.hpp>

#include <optional>
#include <string>
#include <vector>

namespace stereoball::stereo {

/// Which camera of the pair.
enum class Eye { kLeft, kRight };

/// Rectifies whole frames through precomputed LUTs and single points through the lens model.
class Rectifier {
 public:
  /// Builds the look-up tables; fails (naming the field) if calib is invalid.
  static Result<Rectifier> create(const StereoCalibration& calib);

  /// Rectifies both raw frames (any depth/channels cv::remap accepts) into the outputs.
  /// Fails without touching the outputs if a frame is empty or its size differs from
  /// the calibration's image size.
  Status rectify(const cv::Mat& left, const cv::Mat& right, cv::Mat& left_out,
                 cv::Mat& right_out) const;

  /// Rectifies one raw frame of one eye; same checks as rectify().
  Status rectify_eye(Eye eye, const cv::Mat& raw, cv::Mat& out) const;

  /// Rectifies only the rectified-image region roi of one eye into out(roi); out must already
  /// be of the calibration's size and the raw frame's type (pixels outside roi are untouched).
  /// Same checks as rectify_eye, plus out's size/type; roi is clipped to the image.
  Status rectify_eye_region(Eye eye, const cv::Mat& raw, cv::Rect roi, cv::Mat& out) const;
  /// The raw rows [start, end) rectify_eye_region(eye, ..., roi, ...) reads (roi clipped to
  /// the image; the bilinear look-up's lower neighbour included), at least those, never rows
  /// outside the image; empty for an empty roi. A lazily made eye makes these before the call.
  cv::Range raw_rows(Eye eye, cv::Rect roi) const;
  /// Raw (distorted) pixel -> rectified pixel, for callers that only need centres.
  cv::Point2d rectify_point(Eye eye, cv::Point2d raw_px) const;

  /// Batch form of rectify_point, pixels in and out.
  std::vector<cv::Point2d> rectify_points(Eye eye, const std::vector<cv::Point2d>& raw_px) const;

  /// Rectified pixel -> raw (distorted) pixel, the inverse of rectify_point.
  cv::Point2d unrectify_point(Eye eye, cv::Point2d rectified_px) const;

  /// Checks that a frame matches the calibration's image size; error names eye and sizes.
  Status check_size(Eye eye, const cv::Mat& raw) const;

  /// The calibration the tables were built from.
  const StereoCalibration& calibration() const { return calib_; }

 private:
  struct EyeMaps {
    cv::Mat xy;    // CV_16SC2 integer source coordinates
    cv::Mat frac;  // CV_16UC1 interpolation-table index (bilinear weights)
    // Per rectified row and block of kRowBlockCols columns, the first and one past the last raw
    // row its pixels read (CV_32SC2): raw_rows' answer without scanning a box's pixels.
    cv::Mat row_blocks;
  };
  static constexpr int kRowBlockCols = 16;
  static cv::Mat make_row_blocks(const cv::Mat& xy, int raw_rows);
  explicit Rectifier(const StereoCalibration& calib);
  const EyeMaps& maps(Eye eye) const { return eye == Eye::kLeft ? left_ : right_; }

  StereoCalibration calib_;
  EyeMaps left_;
  EyeMaps right_;
};

}  // namespace stereoball::stereo
