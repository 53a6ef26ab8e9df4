#include "stereo/core/sphere_outline.hpp"

#include <cmath>

namespace stereoball::stereo {
namespace {

// Unit vector from the principal point through offset, (1, 0) when offset is zero.
cv::Point2d outward(const cv::Point2d& offset, double length) {
  return length > 0.0 ? offset * (1.0 / length) : cv::Point2d(1.0, 0.0);
}

// Sum of the semi-axes over 2f as a multiple of tau: mean radius = f tau g(t, tau).
double mean_radius_factor(double t, double denominator) {
  const double sec = std::sqrt(1.0 + t * t);
  return 0.5 * (sec * sec / denominator + sec / std::sqrt(denominator));
}

}  // namespace

std::optional<SphereOutline> sphere_outline(const PinholeCamera& camera, const cv::Vec3d& centre_m,
                                            double radius_m) {
  const double f = camera.focal_px;
  const double d2 = centre_m.dot(centre_m);
  if (!(f > 0.0) || !(radius_m > 0.0) || !(centre_m[2] > 0.0) || !(d2 > radius_m * radius_m))
    return std::nullopt;
  const double lateral = std::hypot(centre_m[0], centre_m[1]);
  const double t = lateral / centre_m[2];
  const double tau = radius_m / std::sqrt(d2 - radius_m * radius_m);
  const double denominator = 1.0 - t * t * tau * tau;  // cos(theta+alpha) cos(theta-alpha) > 0
  if (!(denominator > 0.0)) return std::nullopt;
  SphereOutline o;
  o.major_axis = outward({centre_m[0], centre_m[1]}, lateral);
  o.semi_major_px = f * tau * (1.0 + t * t) / denominator;
  o.semi_minor_px = f * tau * std::sqrt(1.0 + t * t) / std::sqrt(denominator);
  o.centre_px = camera.principal_px + o.major_axis * (f * t * (1.0 + tau * tau) / denominator);
  return o;
}

double SphereView::distance_in_radii() const {
  return std::sqrt(1.0 + tan_half_angle * tan_half_angle) / tan_half_angle;
}

double SphereView::depth_m(double radius_m) const {
  return radius_m * distance_in_radii() / std::sqrt(1.0 + tan_off_axis * tan_off_axis);
}

std::optional<SphereView> sphere_from_outline(const PinholeCamera& camera,
                                              const cv::Point2d& outline_centre_px,
                                              double mean_radius_px) {
  const double f = camera.focal_px;
  if (!(f > 0.0) || !(mean_radius_px > 0.0) || !std::isfinite(outline_centre_px.x) ||
      !std::isfinite(outline_centre_px.y))
    return std::nullopt;
  const cv::Point2d offset = outline_centre_px - camera.principal_px;
  const double u = std::hypot(offset.x, offset.y) / f;  // outline centre, normalised
  const double m = mean_radius_px / f;                  // mean radius, normalised
  // Alternate the two relations, each solved for one unknown with the other held: the mean
  // radius for tau, the centre for t (the quadratic of sphere_centre_image_px). They couple
  // through t^2 tau^2 only, so this settles to double precision in a few rounds.
  auto t_from_centre = [u](double tau) {
    const double b = 1.0 + tau * tau;
    return 2.0 * u / (b + std::sqrt(b * b + 4.0 * u * u * tau * tau));
  };
  double tau = m;
  double t = t_from_centre(tau);
  for (int round = 0; round < 16; ++round) {
    const double denominator = 1.0 - t * t * tau * tau;
    if (!(denominator > 0.0)) return std::nullopt;
    tau = m / mean_radius_factor(t, denominator);
    t = t_from_centre(tau);
  }
  const double denominator = 1.0 - t * t * tau * tau;
  if (!(denominator > 0.0) || !(tau > 0.0)) return std::nullopt;
  SphereView v;
  v.tan_off_axis = t;
  v.tan_half_angle = tau;
  v.major_axis = outward(offset, u * f);
  v.axis_ratio = std::sqrt(1.0 + t * t) / std::sqrt(denominator);
  return v;
}

}  // namespace stereoball::stereo
