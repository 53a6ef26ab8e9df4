#pragma once
// The stereo calibration every component shares: camera_server and the
// simulator publish it, ball_detector rectifies and triangulates with it.
// OpenCV conventions; matrices row-major; lengths in metres.

#include <opencv2/core.hpp>

#include <vector>

namespace stereoball::stereo {

/// Intrinsics, extrinsics and rectification of a stereo rig, valid for one image size.
struct StereoCalibration {
  cv::Size image_size;              ///< image size the calibration is valid for, pixels
  cv::Matx33d k1 = cv::Matx33d::eye();  ///< left camera matrix, pixels
  std::vector<double> d1;           ///< left distortion (OpenCV order: k1 k2 p1 p2 [k3 ...])
  cv::Matx33d k2 = cv::Matx33d::eye();  ///< right camera matrix, pixels
  std::vector<double> d2;           ///< right distortion
  cv::Matx33d r = cv::Matx33d::eye();   ///< rotation left -> right
  cv::Vec3d t;                      ///< translation left -> right, metres
  cv::Matx33d r1 = cv::Matx33d::eye();  ///< left rectification rotation
  cv::Matx33d r2 = cv::Matx33d::eye();  ///< right rectification rotation
  cv::Matx34d p1;                   ///< left rectified projection, pixels
  cv::Matx34d p2;                   ///< right rectified projection, pixels (p2(0,3) = -f*B)
  cv::Matx44d q;                    ///< disparity-to-depth matrix
  double rms_px = 0.0;              ///< RMS reprojection error, pixels (0 if unknown)
  std::vector<double> per_pair_rms_px;  ///< per calibration pair, pixels (may be empty)
};

}  // namespace stereoball::stereo
