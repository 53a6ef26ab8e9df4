#include "stereo/core/calibration.hpp"

#include "stereo/core/synthetic_rig.hpp"

#include <gtest/gtest.h>

namespace stereoball::stereo {
namespace {

cv::Vec3d apply(const cv::Matx34d& p, const cv::Vec3d& x) {
  return p * cv::Vec4d(x[0], x[1], x[2], 1.0);
}

TEST(MakeCalibration, GivenKnownRigWhenBuiltThenValidHorizontalWithRigBaseline) {
  // Given the synthetic rig
  const SyntheticRig rig = default_synthetic_rig();
  // When the calibration is built
  const StereoCalibration c = rig.calibration();
  // Then it validates and its baseline is the length of T
  EXPECT_TRUE(validate_calibration(c).ok());
  EXPECT_EQ(c.image_size, rig.size);
  EXPECT_NEAR(baseline_m(c), cv::norm(rig.t), 1e-9);
  EXPECT_GT(focal_px(c), 0.0);
  EXPECT_EQ(c.d1, rig.left.d);
}

TEST(MakeCalibration, GivenPointWhenProjectedThroughRectifiedCamerasThenSameRow) {
  // Given the rig calibration and a point in the left camera frame
  const StereoCalibration c = default_synthetic_rig().calibration();
  const cv::Vec3d x_left(0.2, -0.1, 1.5);
  // When it is projected by both rectified cameras (rectified frame = R1 * left frame)
  const cv::Vec3d in_rect = c.r1 * x_left;
  const cv::Vec3d pl = apply(c.p1, in_rect), pr = apply(c.p2, in_rect);
  // Then both image rows agree and the disparity is positive
  EXPECT_NEAR(pl[1] / pl[2], pr[1] / pr[2], 1e-9);
  EXPECT_GT(pl[0] / pl[2] - pr[0] / pr[2], 0.0);
}

TEST(ValidateCalibration, GivenBrokenFieldsWhenValidatedThenErrorNamesField) {
  const StereoCalibration good = default_synthetic_rig().calibration();
  auto expect_field = [&](auto mutate, const std::string& field) {
    StereoCalibration c = good;
    mutate(c);
    const auto error = validate_calibration(c);
    ASSERT_FALSE(error.ok()) << field;
    EXPECT_EQ(error.error().rfind(field + ":", 0), 0u) << error.error();
  };
  expect_field([](StereoCalibration& c) { c.image_size = {0, 480}; }, "image_size");
  expect_field([](StereoCalibration& c) { c.k1(0, 0) = 0; }, "K1");
  expect_field([](StereoCalibration& c) { c.d1 = {0.1, 0.2, 0.3}; }, "D1");
  expect_field([](StereoCalibration& c) { c.d2[0] = std::nan(""); }, "D2");
  expect_field([](StereoCalibration& c) { c.r = cv::Matx33d::zeros(); }, "R");
  expect_field([](StereoCalibration& c) { c.t = cv::Vec3d(0, 0, 0); }, "T");
  expect_field([](StereoCalibration& c) { c.p2(1, 3) = c.p2(0, 3); }, "P2");
  expect_field([](StereoCalibration& c) { c.q(3, 2) = 0; }, "Q");
}

TEST(CheckCameraOrder, GivenRigInOrderWhenCheckedThenAcceptedAndSwappedRigNamed) {
  // Given the synthetic rig (right camera 12 cm to the right) and the same rig swapped
  const StereoCalibration good = default_synthetic_rig().calibration();
  const StereoCalibration swapped = swapped_cameras(good);
  // When checked, Then only the swapped one is reported, as a negative baseline
  EXPECT_TRUE(check_camera_order(good).ok());
  ASSERT_FALSE(check_camera_order(swapped).ok());
  EXPECT_NE(check_camera_order(swapped).error().find("negative baseline (-0.12"), std::string::npos)
      << check_camera_order(swapped).error();
  EXPECT_NE(check_camera_order(swapped).error().find("swapped"), std::string::npos);
  // and it is still a valid calibration (the order is a separate check), of the same length
  EXPECT_TRUE(validate_calibration(swapped).ok());
  EXPECT_NEAR(baseline_m(swapped), -baseline_m(good), 1e-3);
  EXPECT_NEAR(baseline_m(swapped_cameras(swapped)), baseline_m(good), 1e-9);
}

TEST(CheckImageSize, GivenFramesOfOtherSizeWhenCheckedThenErrorNamesEyeAndSizes) {
  const StereoCalibration c = default_synthetic_rig().calibration();
  EXPECT_TRUE(check_image_size(c, {640, 480}, {640, 480}).ok());
  const auto left = check_image_size(c, {1280, 720}, {640, 480});
  ASSERT_FALSE(left.ok());
  EXPECT_EQ(left.error(), "left image is 1280x720 but the calibration is for 640x480");
  const auto right = check_image_size(c, {640, 480}, {640, 479});
  ASSERT_FALSE(right.ok());
  EXPECT_EQ(right.error(), "right image is 640x479 but the calibration is for 640x480");
}

}  // namespace
}  // namespace stereoball::stereo
