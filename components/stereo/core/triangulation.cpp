#include "stereo/core/triangulation.hpp"

#include <cmath>

namespace stereoball::stereo {

Result<Triangulator> Triangulator::create(const StereoCalibration& calib) {
  if (auto error = validate_calibration(calib); !error) return Error{error.error()};
  return Triangulator(calib);
}

Triangulator::Triangulator(const StereoCalibration& calib)
    : q_(calib.q), focal_px_(stereo::focal_px(calib)), baseline_m_(stereo::baseline_m(calib)) {
  // Q = [1 0 0 -cx; 0 1 0 -cy; 0 0 0 f; 0 0 -1/Tx (cx - cx')/Tx] (cv::stereoRectify).
  principal_left_px_ = {-q_(0, 3), -q_(1, 3)};
  const double cx_right = q_(3, 2) != 0.0 ? -q_(0, 3) + q_(3, 3) / q_(3, 2) : -q_(0, 3);
  principal_right_px_ = {cx_right, -q_(1, 3)};
}

std::optional<cv::Vec3d> Triangulator::sphere_centre_m(const cv::Point2d& left_px,
                                                       const cv::Point2d& right_px,
                                                       double radius_m) const {
  auto p = point_m(left_px.x, right_px.x, 0.5 * (left_px.y + right_px.y));
  if (!p || radius_m <= 0.0) return p;
  // A few rounds: the first distance is short by ~r^2/D, which barely moves the correction.
  for (int round = 0; round < 3; ++round) {
    // Each eye sees the ball from its own centre; the right one is baseline_m along +x.
    const double from_left = cv::norm(*p);
    const double from_right = cv::norm(*p - cv::Vec3d(baseline_m_, 0.0, 0.0));
    if (!(from_left > radius_m) || !(from_right > radius_m)) return p;
    const cv::Point2d l =
        sphere_centre_image_px(left_px, principal_left_px_, focal_px_, radius_m / from_left);
    const cv::Point2d r =
        sphere_centre_image_px(right_px, principal_right_px_, focal_px_, radius_m / from_right);
    const auto next = point_m(l.x, r.x, 0.5 * (l.y + r.y));
    if (!next) return p;
    p = next;
  }
  return p;
}

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

double Triangulator::disparity_for_depth_px(double depth_m) const {
  // depth = q23 / (q32 d + q33)  <=>  d = (q23 / depth - q33) / q32
  return (q_(2, 3) / depth_m - q_(3, 3)) / q_(3, 2);
}

double expected_radius_px(double focal_px, double diameter_m, double depth_m) {
  const double r = 0.5 * diameter_m;
  if (depth_m <= r) return 0.0;
  // The silhouette cone of a sphere has half-angle asin(r / depth).
  return focal_px * r / std::sqrt(depth_m * depth_m - r * r);
}

Status SizeCheckParams::validate() const {
  if (!std::isfinite(ball_diameter_m) || ball_diameter_m <= 0.0 || ball_diameter_m > 5.0) {
    return Error{"ball_diameter_m: must be in (0, 5] metres, got " +
                 std::to_string(ball_diameter_m)};
  }
  if (!std::isfinite(max_relative_error) || max_relative_error <= 0.0 ||
      max_relative_error > 10.0) {
    return Error{"max_relative_error: must be in (0, 10], got " +
                 std::to_string(max_relative_error)};
  }
  return {};
}

SizeCheck check_size_against(const SizeCheckParams& params, double radius_px,
                             double expected_radius_px) {
  SizeCheck c;
  c.expected_radius_px = expected_radius_px;
  if (!(c.expected_radius_px > 0.0) || !(radius_px > 0.0)) return c;
  c.relative_error = (radius_px - c.expected_radius_px) / c.expected_radius_px;
  c.consistent = std::abs(c.relative_error) <= params.max_relative_error;
  return c;
}

cv::Point2d sphere_centre_image_px(const cv::Point2d& outline_centre_px,
                                   const cv::Point2d& principal_px, double focal_px,
                                   double sin_half_angle) {
  const cv::Point2d offset = outline_centre_px - principal_px;
  const double u = std::sqrt(offset.dot(offset)) / focal_px;  // tan of the midpoint angle
  if (!(u > 0.0) || !(focal_px > 0.0) || !(sin_half_angle > 0.0) || !(sin_half_angle < 1.0))
    return outline_centre_px;
  const double s = sin_half_angle;
  const double a2 = s * s / (1.0 - s * s);  // tan^2(alpha)
  // tan(t+a) + tan(t-a) = 2t(1+a^2) / (1 - t^2 a^2) = 2u, solved for t = tan(theta) in the
  // cancellation-free form of the quadratic root.
  const double b = 1.0 + a2;
  const double t = 2.0 * u / (b + std::sqrt(b * b + 4.0 * u * u * a2));
  return principal_px + offset * (t / u);
}

}  // namespace stereoball::stereo
