#include "camera_server/core/frame_builder.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "camera_server/core/format_negotiation.hpp"

namespace stereoball::camera_server {
namespace {

RawImage yuyv_image(int w, int h, uint8_t seed) {
  RawImage r;
  r.fourcc = kFourccYuyv;
  r.width_px = w;
  r.height_px = h;
  r.step_bytes = 2 * w;
  r.bytes.resize(static_cast<size_t>(2) * w * h);
  for (size_t i = 0; i < r.bytes.size(); ++i) r.bytes[i] = static_cast<uint8_t>(i * 7 + seed);
  return r;
}

RawStereoPair pair_of(RawImage l, RawImage r) {
  RawStereoPair p;
  p.seq = 7;
  p.left_stamp_ns = 1000;
  p.right_stamp_ns = 3000;
  p.stamp_ns = 2000;
  p.left = std::move(l);
  p.right = std::move(r);
  return p;
}

TEST(FrameBuilder, GivenYuyvPairAndBgr8WhenBuiltThenConvertedLikeOpenCvWithEyeStamps) {
  FrameBuilder b(FrameBuilderParams{"bgr8"});
  const RawStereoPair p = pair_of(yuyv_image(32, 8, 1), yuyv_image(32, 8, 2));
  auto v = b.step(p);
  ASSERT_TRUE(v.ok()) << v.error();
  EXPECT_EQ(v->encoding, "bgr8");
  EXPECT_EQ(v->seq, 7u);
  EXPECT_EQ(v->stamp_ns, 2000);
  EXPECT_EQ(v->left.capture_stamp_ns, 1000);
  EXPECT_EQ(v->right.capture_stamp_ns, 3000);
  EXPECT_EQ(v->left.step_bytes, 96u);
  EXPECT_EQ(v->left.bytes, 96u * 8);
  cv::Mat ref;
  cv::cvtColor(cv::Mat(8, 32, CV_8UC2, const_cast<uint8_t*>(p.right.bytes.data())), ref,
               cv::COLOR_YUV2BGR_YUYV);
  const cv::Mat right(8, 32, CV_8UC3, const_cast<uint8_t*>(v->right.data));
  EXPECT_EQ(cv::norm(right, ref, cv::NORM_INF), 0.0);
}

TEST(FrameBuilder, GivenNativeEncodingWhenBuiltThenViewPointsAtRawBytes) {
  FrameBuilder b(FrameBuilderParams{"native"});
  const RawStereoPair p = pair_of(yuyv_image(32, 8, 1), yuyv_image(32, 8, 2));
  auto v = b.step(p);
  ASSERT_TRUE(v.ok());
  EXPECT_EQ(v->encoding, "yuyv");
  EXPECT_EQ(v->left.data, p.left.bytes.data());
  EXPECT_EQ(v->left.step_bytes, 64u);
}

TEST(FrameBuilder, GivenMjpegPairWhenBuiltAsBgr8ThenDecoded) {
  cv::Mat img(16, 24, CV_8UC3, cv::Scalar(10, 200, 30));
  RawImage raw;
  raw.fourcc = kFourccMjpeg;
  raw.width_px = 24;
  raw.height_px = 16;
  ASSERT_TRUE(cv::imencode(".jpg", img, raw.bytes));
  FrameBuilder b(FrameBuilderParams{"bgr8"});
  auto v = b.step(pair_of(raw, raw));
  ASSERT_TRUE(v.ok()) << v.error();
  EXPECT_EQ(v->left.width_px, 24u);
  EXPECT_EQ(b.left_bgr().type(), CV_8UC3);
}

TEST(FrameBuilder, GivenCorruptMjpegWhenBuiltThenErrorNamesEye) {
  RawImage raw;
  raw.fourcc = kFourccMjpeg;
  raw.width_px = 24;
  raw.height_px = 16;
  raw.bytes = {0xFF, 0xD8, 0x00, 0x00};
  FrameBuilder b(FrameBuilderParams{"bgr8"});
  auto v = b.step(pair_of(raw, raw));
  ASSERT_FALSE(v.ok());
  EXPECT_EQ(v.error().rfind("left camera:", 0), 0u) << v.error();
}

TEST(FrameBuilder, GivenMixedFormatsWhenBuiltThenError) {
  RawImage m = yuyv_image(8, 2, 0);
  m.fourcc = kFourccMjpeg;
  FrameBuilder b(FrameBuilderParams{"native"});
  auto v = b.step(pair_of(yuyv_image(8, 2, 0), m));
  ASSERT_FALSE(v.ok());
  EXPECT_NE(v.error().find("same pixel format"), std::string::npos);
}

TEST(ViewOfImages, GivenGreyPairWhenViewedThenMono8PointingAtPixels) {
  cv::Mat l(4, 6, CV_8UC1, cv::Scalar(3));
  cv::Mat r(4, 6, CV_8UC1, cv::Scalar(4));
  auto v = stereo::view_of_images(l, r, 5, 99);
  ASSERT_TRUE(v.ok());
  EXPECT_EQ(v->encoding, "mono8");
  EXPECT_EQ(v->left.data, l.data);
  EXPECT_EQ(v->right.bytes, 24u);
  EXPECT_EQ(v->left.capture_stamp_ns, 99);
  EXPECT_FALSE(stereo::view_of_images(l, cv::Mat(4, 6, CV_8UC3), 0, 0).ok());
}

}  // namespace
}  // namespace stereoball::camera_server
