#include "stereo/frame/frame_msg.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace stereoball::stereo {
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

TEST(FillFrameMessage, GivenACompressedViewWhenFilledThenOneStreamPerEyeWithTheDecodedSize) {
  // Given a 352x288 bgr8 view compressed to two (stand-in) streams of different lengths, as
  // FrameCompressor leaves it
  cv::Mat l(288, 352, CV_8UC3, cv::Scalar(1, 2, 3)), r(288, 352, CV_8UC3, cv::Scalar(4, 5, 6));
  auto v = view_of_images(l, r, 3, 55);
  ASSERT_TRUE(v.ok());
  const std::vector<uint8_t> left(1234, 1), right(999, 2);
  v->encoding = "jpeg";
  v->left.step_bytes = v->right.step_bytes = 0;
  v->left.data = left.data();
  v->left.bytes = left.size();
  v->right.data = right.data();
  v->right.bytes = right.size();
  // When filled
  const std::string source = "simulator:test";
  stereoball_msg_StereoFrame m{};
  fill_frame_message(*v, source, m);
  // Then the message follows the compressed-frame contract
  EXPECT_STREQ(m.encoding, "jpeg");
  EXPECT_STREQ(m.source, "simulator:test");
  EXPECT_EQ(m.stamp_ns, 55);
  EXPECT_FALSE(m.rectified);
  EXPECT_EQ(m.left.width_px, 352u);
  EXPECT_EQ(m.right.height_px, 288u);
  EXPECT_EQ(m.left.step_bytes, 0u);
  EXPECT_EQ(m.right.step_bytes, 0u);
  EXPECT_EQ(m.left.data._length, 1234u);
  EXPECT_EQ(m.right.data._length, 999u);
  EXPECT_EQ(m.left.data._buffer, left.data());
  EXPECT_EQ(m.right.data._buffer, right.data());
  EXPECT_FALSE(m.left.data._release);
  EXPECT_EQ(m.left.capture_stamp_ns, 55);
}

}  // namespace
}  // namespace stereoball::stereo
