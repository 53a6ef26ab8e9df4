#include "camera_server/core/frame_scaler.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace stereoball::camera_server {
namespace {

cv::Mat noise(cv::Size size, int type, int seed) {
  cv::Mat m(size, type);
  cv::RNG rng(static_cast<uint64_t>(seed));
  rng.fill(m, cv::RNG::UNIFORM, 0, 256);
  return m;
}

TEST(FrameScaler, GivenABgrPairWhenScaledToHalfWidthThenEyesAreTheAreaResizeWithTheirStamps) {
  // Given a 2304x1296 bgr8 pair whose eyes carry different capture stamps
  const cv::Mat l = noise({2304, 1296}, CV_8UC3, 1), r = noise({2304, 1296}, CV_8UC3, 2);
  auto view = stereo::view_of_images(l, r, 7, 1000);
  ASSERT_TRUE(view.ok());
  view->left.capture_stamp_ns = 990;
  view->right.capture_stamp_ns = 1010;
  // When scaled to 1152 px
  FrameScaler scaler(1152);
  const auto out = scaler.step(*view);
  // Then both eyes are 1152x648, equal to cv::resize with area interpolation, stamps kept
  ASSERT_TRUE(out.ok()) << out.error();
  EXPECT_EQ(out->encoding, "bgr8");
  EXPECT_EQ(out->seq, 7u);
  EXPECT_EQ(out->stamp_ns, 1000);
  EXPECT_EQ(out->left.capture_stamp_ns, 990);
  EXPECT_EQ(out->right.capture_stamp_ns, 1010);
  for (int eye = 0; eye < 2; ++eye) {
    const stereo::EyeView& e = eye == 0 ? out->left : out->right;
    EXPECT_EQ(e.width_px, 1152u);
    EXPECT_EQ(e.height_px, 648u);
    cv::Mat expected;
    cv::resize(eye == 0 ? l : r, expected, {1152, 648}, 0, 0, cv::INTER_AREA);
    EXPECT_EQ(cv::norm(stereo::image_of(e, "bgr8"), expected, cv::NORM_INF), 0.0);
  }
}

TEST(FrameScaler, GivenAMonoPairOfOddAspectWhenScaledThenHeightIsRoundedInProportion) {
  const cv::Mat l = noise({1920, 1080}, CV_8UC1, 3), r = noise({1920, 1080}, CV_8UC1, 4);
  const auto view = stereo::view_of_images(l, r, 0, 0);
  ASSERT_TRUE(view.ok());
  FrameScaler scaler(1000);
  const auto out = scaler.step(*view);
  ASSERT_TRUE(out.ok()) << out.error();
  EXPECT_EQ(out->encoding, "mono8");
  EXPECT_EQ(out->left.width_px, 1000u);
  EXPECT_EQ(out->left.height_px, 563u);
  EXPECT_EQ(scaler.output_size({1920, 1080}), cv::Size(1000, 563));
}

TEST(FrameScaler, GivenNativeBytesOrASmallFrameWhenScaledThenAnErrorNamesTheKey) {
  // Given a yuyv view (native passthrough) and a frame narrower than the publish width
  std::vector<uint8_t> bytes(640 * 480 * 2);
  stereo::FrameView yuyv;
  yuyv.encoding = "yuyv";
  yuyv.left = yuyv.right = stereo::EyeView{0, 640, 480, 1280, bytes.data(), bytes.size()};
  FrameScaler scaler(320);
  const auto native = scaler.step(yuyv);
  ASSERT_FALSE(native.ok());
  EXPECT_NE(native.error().find("publish_width_px"), std::string::npos) << native.error();
  const cv::Mat small = noise({320, 240}, CV_8UC1, 5);
  const auto too_small = scaler.step(stereo::view_of_images(small, small, 0, 0).value());
  ASSERT_FALSE(too_small.ok());
  EXPECT_NE(too_small.error().find("publish_width_px 320"), std::string::npos) << too_small.error();
}

}  // namespace
}  // namespace stereoball::camera_server
