#include "camera_server/node/frame_message.hpp"

#include <gtest/gtest.h>

namespace stereoball::camera_server {
namespace {

TEST(FillFrameMessage, GivenViewWhenFilledThenMessagePointsAtPixelsWithMetadata) {
  cv::Mat l(4, 6, CV_8UC3, cv::Scalar(1, 2, 3));
  cv::Mat r(4, 6, CV_8UC3, cv::Scalar(4, 5, 6));
  auto v = view_of_images(l, r, 12, 777);
  ASSERT_TRUE(v.ok());
  v->right.capture_stamp_ns = 780;
  const std::string source = "files:x";
  stereoball_msg_StereoFrame m{};
  fill_frame_message(*v, source, m);
  EXPECT_EQ(m.seq, 12u);
  EXPECT_EQ(m.stamp_ns, 777);
  EXPECT_STREQ(m.encoding, "bgr8");
  EXPECT_STREQ(m.source, "files:x");
  EXPECT_EQ(m.left.width_px, 6u);
  EXPECT_EQ(m.left.step_bytes, 18u);
  EXPECT_EQ(m.right.capture_stamp_ns, 780);
  EXPECT_EQ(m.left.data._length, 72u);
  EXPECT_EQ(m.right.data._buffer, r.data);
  EXPECT_FALSE(m.left.data._release);
}

TEST(FillCalibrationMessage, GivenCalibrationWhenFilledThenMatricesRowMajorAndSizesCopied) {
  stereo::StereoCalibration c;
  c.image_size = cv::Size(640, 480);
  c.k1 = cv::Matx33d(500, 0, 320, 0, 501, 240, 0, 0, 1);
  c.d1 = {0.1, -0.2, 0, 0, 0.05};
  c.d2 = {0.3};
  c.t = cv::Vec3d(-0.1, 0, 0);
  c.p2 = cv::Matx34d(500, 0, 320, -50, 0, 500, 240, 0, 0, 0, 1, 0);
  c.rms_px = 0.4;
  stereoball_msg_StereoCalibration m{};
  const std::string source = "calib.yaml";  // m.source points into it: must outlive m's use
  fill_calibration_message(c, source, 5, m);
  EXPECT_EQ(m.width_px, 640u);
  EXPECT_EQ(m.height_px, 480u);
  EXPECT_DOUBLE_EQ(m.k1[1 * 3 + 1], 501);  // row 1, col 1
  EXPECT_DOUBLE_EQ(m.k1[0 * 3 + 2], 320);
  EXPECT_EQ(m.d1._length, 5u);
  EXPECT_DOUBLE_EQ(m.d1._buffer[1], -0.2);
  EXPECT_EQ(m.d2._length, 1u);
  EXPECT_DOUBLE_EQ(m.t[0], -0.1);
  EXPECT_DOUBLE_EQ(m.p2[3], -50);
  EXPECT_DOUBLE_EQ(m.rms_px, 0.4);
  EXPECT_STREQ(m.source, "calib.yaml");
}

}  // namespace
}  // namespace stereoball::camera_server
