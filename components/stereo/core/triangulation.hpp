#pragma once
// Triangulation of a rectified centre pair into metres in the left rectified
// camera frame (x right, y down, z forward), plus the independent depth from
// the apparent radius of a ball of known diameter used as a consistency check.

#include "stereo/core/calibration.hpp"
#include "stereo/core/result.hpp"

#include <opencv2/core.hpp>

#include <optional>
#include <string>

namespace stereoball::stereo {

/// Triangulates rectified pixel pairs with the calibration's Q matrix.
class Triangulator {
 public:
  /// Fails (naming the field) if calib is invalid.
  static Result<Triangulator> create(const StereoCalibration& calib);

  /// Point in the left rectified frame, metres, from rectified columns and the (averaged)
  /// row, pixels; nullopt if the disparity puts the point at or behind infinity.
  std::optional<cv::Vec3d> point_m(double x_left_px, double x_right_px, double row_px) const;

  /// Depth (z) for a disparity x_left - x_right, metres; nullopt if not in front.
  std::optional<double> depth_from_disparity_m(double disparity_px) const;

  /// Rectified focal length, pixels.
  double focal_px() const { return focal_px_; }
  /// Baseline, metres.
  double baseline_m() const { return baseline_m_; }

 private:
  explicit Triangulator(const StereoCalibration& calib);
  cv::Matx44d q_;
  double focal_px_;
  double baseline_m_;
};

/// Apparent radius of a sphere of diameter_m whose centre is depth_m ahead, on the
/// optical axis, for focal length focal_px; pixels. 0 if the camera is inside the ball.
double expected_radius_px(double focal_px, double diameter_m, double depth_m);

/// Depth of a sphere of diameter_m that appears with radius_px, metres (inverse of
/// expected_radius_px); nullopt if radius_px <= 0.
std::optional<double> depth_from_radius_m(double focal_px, double diameter_m, double radius_px);

/// Depth from the mean of the radii seen by both eyes, metres; nullopt if either is <= 0.
std::optional<double> depth_from_radii_m(double focal_px, double diameter_m, double radius_left_px,
                                         double radius_right_px);

/// Tolerances of the size-consistency check.
struct SizeCheckParams {
  double ball_diameter_m = 0.2;      ///< true ball diameter, metres
  double max_relative_error = 0.35;  ///< accepted |r_measured - r_expected| / r_expected
  /// Validates ranges; names the bad field and its allowed range, nullopt if OK.
  std::optional<std::string> validate() const;
};

/// Result of comparing a measured radius with the one expected at a depth.
struct SizeCheck {
  bool consistent = false;        ///< relative error within tolerance
  double expected_radius_px = 0;  ///< radius the ball should have at that depth, pixels
  double relative_error = 0;      ///< (measured - expected) / expected
};

/// Is radius_px plausible for a ball of params.ball_diameter_m at depth_m (focal_px pixels)?
SizeCheck check_size(const SizeCheckParams& params, double focal_px, double radius_px,
                     double depth_m);

/// Centre of a sphere of radius_m from the triangulated centres of its two image outlines.
/// The outlines are the images of the circle where the viewing cone touches the sphere; that
/// circle's centre lies r^2/D in front of the sphere's centre (D = distance to the centre), so
/// triangulating image centres underestimates range by about r^2/D. This moves outline_m along
/// its ray to the sphere centre: D - r^2/D = |outline_m|, metres.
cv::Vec3d sphere_centre_from_outline_m(const cv::Vec3d& outline_m, double radius_m);

}  // namespace stereoball::stereo
