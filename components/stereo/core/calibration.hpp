#pragma once
// The stereo calibration every component shares: camera_server and the
// simulator publish it, ball_detector rectifies and triangulates with it.
// OpenCV conventions; matrices row-major; lengths in metres.

#include <opencv2/core.hpp>

#include <optional>
#include <string>
#include <vector>

#include "common/util/result.hpp"

namespace stereoball::stereo {

/// Intrinsics, extrinsics and rectification of a stereo rig, valid for one image size.
struct StereoCalibration {
  cv::Size image_size;                  ///< image size the calibration is valid for, pixels
  cv::Matx33d k1 = cv::Matx33d::eye();  ///< left camera matrix, pixels
  std::vector<double> d1;               ///< left distortion (OpenCV order: k1 k2 p1 p2 [k3 ...])
  cv::Matx33d k2 = cv::Matx33d::eye();  ///< right camera matrix, pixels
  std::vector<double> d2;               ///< right distortion
  cv::Matx33d r = cv::Matx33d::eye();   ///< rotation left -> right
  cv::Vec3d t;                          ///< translation left -> right, metres
  cv::Matx33d r1 = cv::Matx33d::eye();  ///< left rectification rotation
  cv::Matx33d r2 = cv::Matx33d::eye();  ///< right rectification rotation
  cv::Matx34d p1;                       ///< left rectified projection, pixels
  cv::Matx34d p2;                       ///< right rectified projection, pixels (p2(0,3) = -f*B)
  cv::Matx44d q;                        ///< disparity-to-depth matrix
  double rms_px = 0.0;                  ///< RMS reprojection error, pixels (0 if unknown)
  std::vector<double> per_pair_rms_px;  ///< per calibration pair, pixels (may be empty)
};

/// One pinhole camera with lens distortion (OpenCV model).
struct CameraModel {
  cv::Matx33d k = cv::Matx33d::eye();  ///< camera matrix (fx, fy, cx, cy), pixels
  std::vector<double> d;               ///< distortion k1 k2 p1 p2 [k3 ...]; empty means none
};

/// How stereoRectify chooses the rectified view.
struct RectifyOptions {
  /// 0 keeps only valid pixels (zoomed in), 1 keeps every source pixel; -1 = OpenCV default.
  double alpha = 0.0;
  /// Same principal point in both rectified eyes, so disparity is just x_left - x_right.
  bool zero_disparity = true;
};

/// Builds a full calibration (R1 R2 P1 P2 Q) from a known rig via cv::stereoRectify.
/// r, t map left-camera points into the right camera (x_r = r * x_l + t), t in metres.
StereoCalibration make_calibration(const CameraModel& left, const CameraModel& right,
                                   const cv::Matx33d& r, const cv::Vec3d& t, cv::Size size,
                                   const RectifyOptions& options = {});

/// Fills r1 r2 p1 p2 q of calib from its k1 d1 k2 d2 r t image_size.
void rectify_calibration(StereoCalibration& calib, const RectifyOptions& options = {});

/// Checks sizes, finiteness and horizontal rectification; the error names the bad field.
Status validate_calibration(const StereoCalibration& calib);

/// Checks that both frames have the calibration's image size; error names the eye and sizes.
Status check_image_size(const StereoCalibration& calib, cv::Size left, cv::Size right);

/// Rectified focal length, pixels (p1(0,0)).
double focal_px(const StereoCalibration& calib);

/// Baseline between the rectified cameras, metres (-p2(0,3) / p2(0,0)).
double baseline_m(const StereoCalibration& calib);

/// Whether the camera called right really is to the right of the one called left: a negative
/// baseline (swapped cameras) makes every disparity negative, so nothing in front of the rig
/// triangulates. Success for a rig in the right order, else an error saying so (without the
/// fix, which depends on the program).
Status check_camera_order(const StereoCalibration& calib);

/// The same rig with its eyes exchanged (what a rig with swapped cameras calibrates to), with
/// the rectification rebuilt with options.
StereoCalibration swapped_cameras(const StereoCalibration& calib,
                                  const RectifyOptions& options = {});

/// Distortion vector lengths OpenCV accepts: 0 (none), 4, 5, 8, 12 or 14.
bool is_valid_distortion_size(std::size_t n);

}  // namespace stereoball::stereo
