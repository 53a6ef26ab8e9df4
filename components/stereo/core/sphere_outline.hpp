#pragma once
// How a sphere images in a pinhole camera, and back: off the optical axis its outline is an
// ellipse, stretched along the line from the principal point, centred farther out than the
// projection of the sphere's centre. With theta the angle of the sphere's centre off the axis
// and alpha the half-angle it subtends (t = tan(theta), tau = tan(alpha), focal f), the outline
// spans tan(theta - alpha) .. tan(theta + alpha) along that line, so
//   semi-major a = f tau (1 + t^2) / (1 - t^2 tau^2),
//   semi-minor b = f tau sqrt(1 + t^2) / sqrt(1 - t^2 tau^2),
//   centre at f t (1 + tau^2) / (1 - t^2 tau^2) from the principal point.
// On the axis a = b = f tau. All in the undistorted (rectified) image.

#include <opencv2/core.hpp>

#include <optional>

namespace stereoball::stereo {

/// An undistorted pinhole camera: focal length and principal point, pixels.
struct PinholeCamera {
  double focal_px = 0.0;
  cv::Point2d principal_px;
};

/// The outline of a sphere in the image.
struct SphereOutline {
  cv::Point2d centre_px;     ///< centre of the ellipse
  double semi_major_px = 0;  ///< along major_axis
  double semi_minor_px = 0;  ///< across it
  cv::Point2d major_axis;    ///< unit vector from the principal point outwards ((1, 0) on axis)
  /// Mean of the semi-axes: what a least-squares circle through the outline measures.
  double mean_radius_px() const { return 0.5 * (semi_major_px + semi_minor_px); }
};

/// Outline of the sphere of radius radius_m centred at centre_m (camera frame: x right, y down,
/// z forward); nullopt if the camera is inside it or it reaches 90 degrees off the axis (the
/// outline is then not a bounded ellipse).
std::optional<SphereOutline> sphere_outline(const PinholeCamera& camera, const cv::Vec3d& centre_m,
                                            double radius_m);

/// What an outline says about the sphere behind it.
struct SphereView {
  double tan_off_axis = 0;    ///< t = tan(theta) of the sphere's centre
  double tan_half_angle = 0;  ///< tau = tan(alpha)
  cv::Point2d major_axis;     ///< unit vector from the principal point outwards ((1, 0) on axis)
  double axis_ratio = 1.0;    ///< semi-major / semi-minor of the outline, >= 1
  /// Distance of the sphere's centre in sphere radii (1 / sin(alpha)).
  double distance_in_radii() const;
  /// Depth (z) of the sphere's centre for a sphere of radius_m, metres.
  double depth_m(double radius_m) const;
};

/// Inverse of sphere_outline from what a circle fit measures: the outline's centre and mean
/// radius (mean of the semi-axes), pixels. nullopt for a non-positive radius or focal length, or
/// an outline no sphere makes.
std::optional<SphereView> sphere_from_outline(const PinholeCamera& camera,
                                              const cv::Point2d& outline_centre_px,
                                              double mean_radius_px);

}  // namespace stereoball::stereo
