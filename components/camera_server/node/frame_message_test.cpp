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

}  // namespace
}  // namespace stereoball::camera_server
