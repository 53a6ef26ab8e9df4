#pragma once
// Pinhole camera with OpenCV's radial-tangential lens distortion (k1 k2 p1 p2 k3).

#include <array>
#include <optional>

#include "simulator/core/sim_params.hpp"
#include "simulator/core/vec3.hpp"

namespace stereoball::simulator {

/// A 2D point (pixels or normalized image coordinates).
struct Point2 {
  double x = 0.0;
  double y = 0.0;
};

/// Camera matrix entries (pixels) and distortion coefficients of one eye.
struct Intrinsics {
  double fx = 1.0, fy = 1.0, cx = 0.0, cy = 0.0;  ///< pixels
  std::array<double, 5> dist{};                   ///< k1 k2 p1 p2 k3
};

/// Intrinsics of an eye for an image of width_px x height_px (fx from the horizontal FOV).
Intrinsics make_intrinsics(const EyeParams& eye, int width_px, int height_px);

/// Applies the distortion model to a normalized undistorted point.
Point2 distort_normalized(const std::array<double, 5>& dist, Point2 p);

/// Inverts the distortion model (Newton); nullopt if it does not converge.
std::optional<Point2> undistort_normalized(const std::array<double, 5>& dist, Point2 pd);

/// Raw (distorted) pixel of a point in the camera frame (x right, y down, z forward, z > 0).
Point2 project_raw(const Intrinsics& k, const Vec3d& p_cam);

}  // namespace stereoball::simulator
