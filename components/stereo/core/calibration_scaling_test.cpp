#include "stereo/core/calibration_scaling.hpp"

#include <gtest/gtest.h>

#include "stereo/core/rectifier.hpp"
#include "stereo/core/synthetic_rig.hpp"

namespace stereoball::stereo {
namespace {

// Where a pixel coordinate of the original image lands in the resized one (pixel centres).
cv::Point2d scaled_px(cv::Point2d p, double sx, double sy) {
  return {sx * (p.x + 0.5) - 0.5, sy * (p.y + 0.5) - 0.5};
}

cv::Point2d project(const cv::Matx34d& p, const cv::Vec3d& x) {
  const cv::Vec3d h = p * cv::Vec4d(x[0], x[1], x[2], 1.0);
  return {h[0] / h[2], h[1] / h[2]};
}

TEST(ScaledSize, GivenACaptureSizeWhenScaledToAWidthThenTheHeightKeepsTheAspectRatio) {
  EXPECT_EQ(scaled_size({2304, 1296}, 1152), cv::Size(1152, 648));
  EXPECT_EQ(scaled_size({640, 480}, 320), cv::Size(320, 240));
  EXPECT_EQ(scaled_size({1920, 1080}, 1000), cv::Size(1000, 563));  // 562.5 rounds up
  EXPECT_EQ(scaled_size({640, 480}, 0), cv::Size());
}

TEST(ScaleCalibration, GivenTheSyntheticRigWhenHalvedThenEveryProjectionIsTheScaledProjection) {
  // Given the synthetic rig's calibration (640x480) and points in front of it
  const SyntheticRig rig = default_synthetic_rig();
  const StereoCalibration full = rig.calibration();
  // When it is scaled to 320x240
  const auto half = scale_calibration(full, {320, 240});
  ASSERT_TRUE(half.ok()) << half.error();
  EXPECT_EQ(half->image_size, cv::Size(320, 240));
  // Then the rectified projections, the focal length and the baseline follow the scale
  EXPECT_NEAR(focal_px(*half), 0.5 * focal_px(full), 1e-9);
  EXPECT_NEAR(baseline_m(*half), baseline_m(full), 1e-12);
  EXPECT_EQ(half->d1, full.d1);
  EXPECT_EQ(half->r1, full.r1);
  for (const cv::Vec3d& x : {cv::Vec3d(0.2, -0.1, 1.5), cv::Vec3d(-0.4, 0.3, 3.0)}) {
    const cv::Vec3d in_rect = full.r1 * x;
    for (int eye = 0; eye < 2; ++eye) {
      const cv::Point2d expected =
          scaled_px(project(eye == 0 ? full.p1 : full.p2, in_rect), 0.5, 0.5);
      const cv::Point2d got = project(eye == 0 ? half->p1 : half->p2, in_rect);
      EXPECT_NEAR(got.x, expected.x, 1e-9);
      EXPECT_NEAR(got.y, expected.y, 1e-9);
    }
    // and Q gives the same 3D point for the scaled pixel and disparity
    const cv::Point2d l = project(half->p1, in_rect), r = project(half->p2, in_rect);
    const cv::Vec4d h = half->q * cv::Vec4d(l.x, l.y, l.x - r.x, 1.0);
    EXPECT_NEAR(h[0] / h[3], in_rect[0], 1e-9);
    EXPECT_NEAR(h[1] / h[3], in_rect[1], 1e-9);
    EXPECT_NEAR(h[2] / h[3], in_rect[2], 1e-9);
  }
}

TEST(ScaleCalibration, GivenARawPointWhenRectifiedWithTheScaledCalibrationThenItIsScaled) {
  // Given the rig, the calibration scaled to 400x300 (0.625) and raw pixels of a 3D point
  const SyntheticRig rig = default_synthetic_rig();
  const StereoCalibration full = rig.calibration();
  const auto scaled = scale_calibration(full, {400, 300});
  ASSERT_TRUE(scaled.ok()) << scaled.error();
  const Rectifier rect_full = Rectifier::create(full).value();
  const Rectifier rect_scaled = Rectifier::create(*scaled).value();
  const double s = 0.625;
  const cv::Point3d x(0.3, 0.2, 2.0);
  // When the scaled raw pixel is rectified with the scaled calibration
  for (const Eye eye : {Eye::kLeft, Eye::kRight}) {
    const cv::Point2d raw = eye == Eye::kLeft ? rig.project_left(x) : rig.project_right(x);
    const cv::Point2d got = rect_scaled.rectify_point(eye, scaled_px(raw, s, s));
    // Then it lands where the full-size rectified pixel lands after scaling
    const cv::Point2d expected = scaled_px(rect_full.rectify_point(eye, raw), s, s);
    EXPECT_NEAR(got.x, expected.x, 1e-6);
    EXPECT_NEAR(got.y, expected.y, 1e-6);
  }
}

TEST(ScaleCalibration, GivenAnEmptySizeOrABrokenCalibrationWhenScaledThenAnErrorNamesIt) {
  const StereoCalibration full = default_synthetic_rig().calibration();
  const auto empty = scale_calibration(full, {0, 240});
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.error().find("0x240"), std::string::npos) << empty.error();
  StereoCalibration broken = full;
  broken.k1(0, 0) = 0;
  const auto bad = scale_calibration(broken, {320, 240});
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("K1"), std::string::npos) << bad.error();
}

}  // namespace
}  // namespace stereoball::stereo
