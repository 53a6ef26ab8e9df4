#include "stereo/core/synthetic_rig.hpp"

#include "stereo/core/rectifier.hpp"
#include "stereo/core/triangulation.hpp"

#include <cmath>

namespace stereoball::stereo {

DepthErrorFigures measure_depth_error(const SyntheticRig& rig, double depth_m, double sigma_px,
                                      int n, std::uint64_t seed) {
  const StereoCalibration c = rig.calibration();
  const Rectifier rect = Rectifier::create(c).value();
  const Triangulator tri = Triangulator::create(c).value();
  cv::RNG rng(seed);
  DepthErrorFigures f;
  f.depth_m = depth_m;
  double sum_sq = 0.0;
  int used = 0;
  for (int i = 0; i < n; ++i) {
    const cv::Point3d p(rng.uniform(-0.1, 0.1) * depth_m, rng.uniform(-0.1, 0.1) * depth_m,
                        depth_m);
    auto noisy = [&](cv::Point2d q) {
      return q + cv::Point2d(rng.gaussian(sigma_px), rng.gaussian(sigma_px));
    };
    const cv::Point2d l = rect.rectify_point(Eye::kLeft, noisy(rig.project_left(p)));
    const cv::Point2d r = rect.rectify_point(Eye::kRight, noisy(rig.project_right(p)));
    const auto x = tri.point_m(l.x, r.x, 0.5 * (l.y + r.y));
    if (!x) {
      ++f.failures;
      continue;
    }
    const double err = (*x)[2] - (c.r1 * cv::Vec3d(p.x, p.y, p.z))[2];
    sum_sq += err * err;
    ++used;
  }
  f.rms_error_m = used ? std::sqrt(sum_sq / used) : 0.0;
  // Raw-pixel noise reaches the rectified images scaled by f_rect / f_raw.
  const double f_raw =
      0.25 * (rig.left.k(0, 0) + rig.left.k(1, 1) + rig.right.k(0, 0) + rig.right.k(1, 1));
  f.d_disparity_px = std::sqrt(2.0) * sigma_px * focal_px(c) / f_raw;
  f.bound_m = depth_m * depth_m * f.d_disparity_px / (focal_px(c) * baseline_m(c));
  return f;
}

}  // namespace stereoball::stereo
