// stereo/calibration message <-> StereoCalibration: exact round trip, bad fields named.

#include "stereo/msg/calibration_msg.hpp"

#include <gtest/gtest.h>

#include "stereo/core/synthetic_rig.hpp"

namespace sb = stereoball;

TEST(CalibrationMessage, GivenSyntheticRig_ThenRoundTripsExactly) {
  const auto calib = sb::stereo::default_synthetic_rig().calibration();
  const std::string source = "synthetic";
  const auto msg = sb::stereo::calibration_to_message(calib, 123, source);
  EXPECT_EQ(msg.stamp_ns, 123);
  EXPECT_EQ(msg.width_px, 640u);
  EXPECT_EQ(msg.d1._length, calib.d1.size());
  EXPECT_STREQ(msg.source, "synthetic");
  const auto back = sb::stereo::calibration_from_message(msg);
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(back->image_size, calib.image_size);
  EXPECT_EQ(back->d1, calib.d1);
  EXPECT_EQ(back->d2, calib.d2);
  EXPECT_EQ(cv::norm(back->k1 - calib.k1), 0.0);
  EXPECT_EQ(cv::norm(back->p2 - calib.p2), 0.0);
  EXPECT_EQ(cv::norm(back->q - calib.q), 0.0);
  EXPECT_EQ(cv::norm(back->t - calib.t), 0.0);
}

TEST(CalibrationMessage, GivenBadFields_ThenErrorNamesThem) {
  auto calib = sb::stereo::default_synthetic_rig().calibration();
  calib.d1 = {0.1, 0.2, 0.3};
  const std::string source;
  auto msg = sb::stereo::calibration_to_message(calib, 0, source);
  auto r = sb::stereo::calibration_from_message(msg);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("d1"), std::string::npos) << r.error();

  calib = sb::stereo::default_synthetic_rig().calibration();
  msg = sb::stereo::calibration_to_message(calib, 0, source);
  msg.width_px = 0;
  r = sb::stereo::calibration_from_message(msg);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("image size"), std::string::npos) << r.error();

  msg = sb::stereo::calibration_to_message(calib, 0, source);
  msg.k2[0] = 0.0;  // zero focal length
  r = sb::stereo::calibration_from_message(msg);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("K2"), std::string::npos) << r.error();
}

// Given a calibration, the message's matrices are row-major copies and the sequences and
// source point into the caller's storage without ownership.
TEST(CalibrationMessage, GivenCalibration_ThenFieldsRowMajorAndBorrowed) {
  const auto calib = sb::stereo::default_synthetic_rig().calibration();
  const std::string source = "true";
  const auto m = sb::stereo::calibration_to_message(calib, 7, source);
  EXPECT_EQ(m.height_px, static_cast<std::uint32_t>(calib.image_size.height));
  EXPECT_DOUBLE_EQ(m.k1[2], calib.k1(0, 2));
  EXPECT_DOUBLE_EQ(m.p2[3], calib.p2(0, 3));
  EXPECT_DOUBLE_EQ(m.q[11], calib.q(2, 3));
  EXPECT_DOUBLE_EQ(m.t[0], calib.t[0]);
  ASSERT_EQ(m.d2._length, calib.d2.size());
  EXPECT_EQ(m.d2._buffer, calib.d2.data());
  EXPECT_FALSE(m.d2._release);
  EXPECT_EQ(m.source, source.c_str());
}
