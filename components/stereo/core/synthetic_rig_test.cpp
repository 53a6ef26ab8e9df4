// Synthetic acceptance (issue 4): known rig, 0.1 px pixel noise, point
// rectification and triangulation; the depth error must sit at the
// noise-limited bound dZ = Z^2 * d_disparity / (f * B) within 20 %.

#include "stereo/core/synthetic_rig.hpp"
#include "stereo/core/rectifier.hpp"
#include "stereo/core/triangulation.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace stereoball::stereo {
namespace {

struct DepthErrorFigures {
  double rms_error_m = 0;  // measured RMS depth error
  double bound_m = 0;      // Z^2 * d_disparity / (f * B)
};

// Projects n points at depth z near the optical axis, adds sigma_px noise to every raw pixel
// coordinate, rectifies and triangulates.
DepthErrorFigures measure(double z, double sigma_px, int n) {
  const SyntheticRig rig = default_synthetic_rig();
  const StereoCalibration c = rig.calibration();
  const Rectifier rect = Rectifier::create(c).value();
  const Triangulator tri = Triangulator::create(c).value();
  cv::RNG rng(1234 + static_cast<uint64_t>(z * 100));
  double sum_sq = 0.0;
  for (int i = 0; i < n; ++i) {
    const cv::Point3d p(rng.uniform(-0.1, 0.1) * z, rng.uniform(-0.1, 0.1) * z, z);
    auto noisy = [&](cv::Point2d q) {
      return q + cv::Point2d(rng.gaussian(sigma_px), rng.gaussian(sigma_px));
    };
    const cv::Point2d l = rect.rectify_point(Eye::kLeft, noisy(rig.project_left(p)));
    const cv::Point2d r = rect.rectify_point(Eye::kRight, noisy(rig.project_right(p)));
    const auto x = tri.point_m(l.x, r.x, 0.5 * (l.y + r.y));
    const double truth = (c.r1 * cv::Vec3d(p.x, p.y, p.z))[2];
    const double err = x ? (*x)[2] - truth : 1e9;
    sum_sq += err * err;
  }
  // Raw-pixel noise reaches the rectified images scaled by f_rect / f_raw.
  const double f_raw =
      0.25 * (rig.left.k(0, 0) + rig.left.k(1, 1) + rig.right.k(0, 0) + rig.right.k(1, 1));
  const double d_disparity = std::sqrt(2.0) * sigma_px * focal_px(c) / f_raw;
  return {std::sqrt(sum_sq / n), z * z * d_disparity / (focal_px(c) * baseline_m(c))};
}

TEST(SyntheticAcceptance, GivenNoisyPixelsAt1mAnd2mWhenTriangulatedThenDepthErrorAtNoiseBound) {
  for (double z : {1.0, 2.0}) {
    // Given 2000 points at depth z seen with 0.1 px noise
    // When rectified and triangulated
    const DepthErrorFigures f = measure(z, 0.1, 2000);
    // Then the RMS depth error is the noise-limited bound within 20 %
    EXPECT_LE(f.rms_error_m, 1.2 * f.bound_m) << "z=" << z;
    EXPECT_GE(f.rms_error_m, 0.8 * f.bound_m) << "z=" << z;
    RecordProperty("rms_error_mm_at_" + std::to_string(static_cast<int>(z)) + "m",
                   std::to_string(f.rms_error_m * 1e3));
  }
}

TEST(SyntheticAcceptance, GivenNoNoiseWhenTriangulatedThenDepthExact) {
  const DepthErrorFigures f = measure(2.0, 0.0, 200);
  EXPECT_LT(f.rms_error_m, 1e-6);
}

}  // namespace
}  // namespace stereoball::stereo
