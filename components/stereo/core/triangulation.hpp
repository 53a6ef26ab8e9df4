#pragma once
// Triangulation of a rectified centre pair into metres in the left rectified
// camera frame (x right, y down, z forward), plus the independent depth from
// the apparent radius of a ball of known diameter used as a consistency check.

#include "common/util/result.hpp"
#include "stereo/core/calibration.hpp"

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
  /// Disparity x_left - x_right of a point depth_m ahead (> 0), pixels: depth_from_disparity_m
  /// inverted.
  double disparity_for_depth_px(double depth_m) const;

  /// Centre of a sphere of radius_m, left rectified frame, metres, from the centres of its
  /// image outlines (rectified pixels, rows averaged): each eye's centre is moved to the
  /// projection of the sphere's centre (sphere_centre_image_px, at the distance of a first
  /// triangulation) before triangulating. Without this, range comes out about r^2/D short and
  /// an off-axis ball about (r/D)^2 of its offset too far out. nullopt if not in front.
  std::optional<cv::Vec3d> sphere_centre_m(const cv::Point2d& left_px, const cv::Point2d& right_px,
                                           double radius_m) const;

  /// Principal points of the rectified left and right images, pixels (rows are shared).
  cv::Point2d principal_left_px() const { return principal_left_px_; }
  cv::Point2d principal_right_px() const { return principal_right_px_; }
  /// Rectified focal length, pixels.
  double focal_px() const { return focal_px_; }
  /// Baseline, metres.
  double baseline_m() const { return baseline_m_; }

 private:
  explicit Triangulator(const StereoCalibration& calib);
  cv::Matx44d q_;
  cv::Point2d principal_left_px_;
  cv::Point2d principal_right_px_;
  double focal_px_;
  double baseline_m_;
};

/// Apparent radius of a sphere of diameter_m whose centre is depth_m ahead, on the
/// optical axis, for focal length focal_px; pixels. 0 if the camera is inside the ball.
/// (Off the axis the outline is larger: see sphere_outline.)
double expected_radius_px(double focal_px, double diameter_m, double depth_m);

/// Tolerances of the size-consistency check.
struct SizeCheckParams {
  double ball_diameter_m = 0.2;      ///< true ball diameter, metres
  double max_relative_error = 0.35;  ///< accepted |r_measured - r_expected| / r_expected
  /// Success, or an error naming the bad field and its allowed range.
  Status validate() const;
};

/// Result of comparing a measured radius with the one expected at a depth.
struct SizeCheck {
  bool consistent = false;        ///< relative error within tolerance
  double expected_radius_px = 0;  ///< radius the ball should have at that depth, pixels
  double relative_error = 0;      ///< (measured - expected) / expected
};

/// Is radius_px within params' tolerance of expected_radius_px (inconsistent if either <= 0)?
/// The expected radius of a ball anywhere in the view: sphere_outline's mean radius.
SizeCheck check_size_against(const SizeCheckParams& params, double radius_px,
                             double expected_radius_px);

/// Where the centre of a sphere projects, from the centre of its image outline, pixels.
/// An off-axis sphere images as an ellipse stretched away from the principal point, and its
/// centre lies farther out than the centre's projection: at angle theta off the axis with
/// half-angle alpha the outline spans tan(theta - alpha) .. tan(theta + alpha) (normalised
/// units) along the radial line. Inverting that midpoint shifts the point back toward the
/// principal point. sin_half_angle = sphere radius / distance of its centre, in [0, 1).
cv::Point2d sphere_centre_image_px(const cv::Point2d& outline_centre_px,
                                   const cv::Point2d& principal_px, double focal_px,
                                   double sin_half_angle);

}  // namespace stereoball::stereo
