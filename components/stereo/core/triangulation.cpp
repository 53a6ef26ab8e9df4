#include "stereo/core/triangulation.hpp"

#include <cmath>

namespace stereoball::stereo {

Result<Triangulator> Triangulator::create(const StereoCalibration& calib) {
  if (auto error = validate_calibration(calib)) return Result<Triangulator>::fail(*error);
  return Result<Triangulator>::ok(Triangulator(calib));
}

Triangulator::Triangulator(const StereoCalibration& calib)
    : q_(calib.q), focal_px_(stereo::focal_px(calib)), baseline_m_(stereo::baseline_m(calib)) {}

std::optional<cv::Vec3d> Triangulator::point_m(double x_left_px, double x_right_px,
                                               double row_px) const {
  const cv::Vec4d h = q_ * cv::Vec4d(x_left_px, row_px, x_left_px - x_right_px, 1.0);
  // w is proportional to the disparity: w <= 0 means at infinity or behind the rig.
  if (!(h[3] > 0.0)) return std::nullopt;
  return cv::Vec3d(h[0] / h[3], h[1] / h[3], h[2] / h[3]);
}

std::optional<double> Triangulator::depth_from_disparity_m(double disparity_px) const {
  const double w = q_(3, 2) * disparity_px + q_(3, 3);
  if (!(w > 0.0)) return std::nullopt;
  return q_(2, 3) / w;
}

double expected_radius_px(double focal_px, double diameter_m, double depth_m) {
  const double r = 0.5 * diameter_m;
  if (depth_m <= r) return 0.0;
  // The silhouette cone of a sphere has half-angle asin(r / depth).
  return focal_px * r / std::sqrt(depth_m * depth_m - r * r);
}

std::optional<double> depth_from_radius_m(double focal_px, double diameter_m, double radius_px) {
  if (!(radius_px > 0.0)) return std::nullopt;
  const double r = 0.5 * diameter_m;
  const double ratio = focal_px / radius_px;
  return r * std::sqrt(1.0 + ratio * ratio);
}

std::optional<double> depth_from_radii_m(double focal_px, double diameter_m, double radius_left_px,
                                         double radius_right_px) {
  if (!(radius_left_px > 0.0) || !(radius_right_px > 0.0)) return std::nullopt;
  return depth_from_radius_m(focal_px, diameter_m, 0.5 * (radius_left_px + radius_right_px));
}

std::optional<std::string> SizeCheckParams::validate() const {
  if (!std::isfinite(ball_diameter_m) || ball_diameter_m <= 0.0 || ball_diameter_m > 5.0) {
    return "ball_diameter_m: must be in (0, 5] metres, got " + std::to_string(ball_diameter_m);
  }
  if (!std::isfinite(max_relative_error) || max_relative_error <= 0.0 ||
      max_relative_error > 10.0) {
    return "max_relative_error: must be in (0, 10], got " + std::to_string(max_relative_error);
  }
  return std::nullopt;
}

SizeCheck check_size(const SizeCheckParams& params, double focal_px, double radius_px,
                     double depth_m) {
  SizeCheck c;
  c.expected_radius_px = expected_radius_px(focal_px, params.ball_diameter_m, depth_m);
  if (c.expected_radius_px <= 0.0 || !(radius_px > 0.0)) return c;
  c.relative_error = (radius_px - c.expected_radius_px) / c.expected_radius_px;
  c.consistent = std::abs(c.relative_error) <= params.max_relative_error;
  return c;
}

cv::Vec3d sphere_centre_from_outline_m(const cv::Vec3d& outline_m, double radius_m) {
  const double d = cv::norm(outline_m);
  if (d <= 0.0 || radius_m <= 0.0) return outline_m;
  const double centre_distance = 0.5 * (d + std::sqrt(d * d + 4.0 * radius_m * radius_m));
  return outline_m * (centre_distance / d);
}

}  // namespace stereoball::stereo
