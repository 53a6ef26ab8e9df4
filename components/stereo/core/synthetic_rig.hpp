#pragma once
// A fixed, realistic synthetic stereo rig (640x480, 12 cm baseline, lens
// distortion, small rotation between the cameras) and exact projection of
// 3D points into its raw images. Used by tests and the benchmark.

#include "stereo/core/calibration.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include <cstdint>

namespace stereoball::stereo {

/// The known rig: left/right models and the left -> right transform (t in metres).
struct SyntheticRig {
  CameraModel left;
  CameraModel right;
  cv::Vec3d rvec;  ///< left -> right rotation vector, radians
  cv::Vec3d t;     ///< left -> right translation, metres
  cv::Size size;   ///< image size, pixels

  /// Rotation matrix of rvec.
  cv::Matx33d r() const {
    cv::Matx33d m;
    cv::Rodrigues(rvec, m);
    return m;
  }
  /// The calibration the rig implies (stereoRectify with default options).
  StereoCalibration calibration() const { return make_calibration(left, right, r(), t, size); }

  /// Raw (distorted) pixel of a point given in the left camera frame, metres.
  cv::Point2d project_left(const cv::Point3d& p_m) const { return project(p_m, {}, {}, left); }
  /// Raw (distorted) pixel in the right image of a point given in the left camera frame.
  cv::Point2d project_right(const cv::Point3d& p_m) const { return project(p_m, rvec, t, right); }

 private:
  static cv::Point2d project(const cv::Point3d& p, const cv::Vec3d& rv, const cv::Vec3d& tv,
                             const CameraModel& cam) {
    std::vector<cv::Point3d> obj{p};
    std::vector<cv::Point2d> img;
    cv::projectPoints(obj, rv, tv, cv::Mat(cam.k), cv::Mat(cam.d, true), img);
    return img.front();
  }
};

/// Measured vs noise-limited depth error of a Monte Carlo run (see measure_depth_error).
struct DepthErrorFigures {
  double depth_m = 0;         ///< true depth of the points, metres
  double rms_error_m = 0;     ///< measured RMS depth error, metres
  double bound_m = 0;         ///< Z^2 * d_disparity / (f * B), metres
  double d_disparity_px = 0;  ///< disparity noise in rectified pixels: sqrt(2) sigma f_rect/f_raw
  int failures = 0;           ///< points that did not triangulate
};

/// Projects n random points at depth_m within +-0.1 rad of the axis into the raw images,
/// adds Gaussian noise of sigma_px to every pixel coordinate, point-rectifies, applies the
/// averaged row and triangulates; compares the depth error with the noise-limited bound.
DepthErrorFigures measure_depth_error(const SyntheticRig& rig, double depth_m, double sigma_px,
                                      int n, std::uint64_t seed);

/// The rig used throughout the tests: fx ~600 px, B = 0.12 m, barrel distortion.
inline SyntheticRig default_synthetic_rig() {
  SyntheticRig rig;
  rig.left.k = cv::Matx33d(600, 0, 322, 0, 601, 238, 0, 0, 1);
  rig.left.d = {-0.21, 0.06, 0.0008, -0.0005, 0.0};
  rig.right.k = cv::Matx33d(606, 0, 317, 0, 605, 244, 0, 0, 1);
  rig.right.d = {-0.19, 0.05, -0.0006, 0.0004, 0.0};
  rig.rvec = cv::Vec3d(0.01, -0.02, 0.006);
  rig.t = cv::Vec3d(-0.12, 0.002, -0.001);
  rig.size = cv::Size(640, 480);
  return rig;
}

}  // namespace stereoball::stereo
