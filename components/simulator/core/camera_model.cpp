#include "simulator/core/camera_model.hpp"

#include <cmath>
#include <numbers>

namespace stereoball::simulator {

Intrinsics make_intrinsics(const EyeParams& eye, int width_px, int height_px) {
  Intrinsics k;
  const double half = eye.hfov_deg * std::numbers::pi / 360.0;
  k.fx = 0.5 * width_px / std::tan(half);
  k.fy = k.fx * eye.fy_over_fx;
  // Pixel centres sit on integer coordinates, so the image centre is (w-1)/2.
  k.cx = 0.5 * (width_px - 1) + eye.cx_offset_px;
  k.cy = 0.5 * (height_px - 1) + eye.cy_offset_px;
  k.dist = eye.distortion;
  return k;
}

Point2 distort_normalized(const std::array<double, 5>& d, Point2 p) {
  const double r2 = p.x * p.x + p.y * p.y;
  const double radial = 1.0 + r2 * (d[0] + r2 * (d[1] + r2 * d[4]));
  const double xy = p.x * p.y;
  return {p.x * radial + 2.0 * d[2] * xy + d[3] * (r2 + 2.0 * p.x * p.x),
          p.y * radial + d[2] * (r2 + 2.0 * p.y * p.y) + 2.0 * d[3] * xy};
}

std::optional<Point2> undistort_normalized(const std::array<double, 5>& d, Point2 pd) {
  Point2 p = pd;
  constexpr double kStep = 1e-7;
  for (int it = 0; it < 50; ++it) {
    const Point2 f = distort_normalized(d, p);
    const double ex = f.x - pd.x, ey = f.y - pd.y;
    if (ex * ex + ey * ey < 1e-26) return p;
    // Numerical Jacobian: cheap enough because ray tables are built once.
    const Point2 fx = distort_normalized(d, {p.x + kStep, p.y});
    const Point2 fy = distort_normalized(d, {p.x, p.y + kStep});
    const double a = (fx.x - f.x) / kStep, b = (fy.x - f.x) / kStep;
    const double c = (fx.y - f.y) / kStep, e = (fy.y - f.y) / kStep;
    const double det = a * e - b * c;
    if (std::abs(det) < 1e-12) return std::nullopt;
    p.x -= (e * ex - b * ey) / det;
    p.y -= (-c * ex + a * ey) / det;
  }
  const Point2 f = distort_normalized(d, p);
  if (std::hypot(f.x - pd.x, f.y - pd.y) < 1e-9) return p;
  return std::nullopt;
}

Point2 project_raw(const Intrinsics& k, const Vec3d& p_cam) {
  const Point2 n = distort_normalized(k.dist, {p_cam.x / p_cam.z, p_cam.y / p_cam.z});
  return {k.fx * n.x + k.cx, k.fy * n.y + k.cy};
}

}  // namespace stereoball::simulator
