// The stereo/preview encoder: JPEGs that decode to the preview size with the frame's seq and
// stamps, wide eyes scaled down, the source size kept, and named errors for bad input.

#include "stereo/frame/preview_encoder.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <string>
#include <vector>

// GCC 12 reports a false -Wrestrict on std::string assignment from a literal (GCC PR 105651).
#pragma GCC diagnostic ignored "-Wrestrict"

namespace stereoball::stereo {
namespace {

cv::Mat gradient(int width, int height) {
  cv::Mat img(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      img.at<cv::Vec3b>(y, x) =
          cv::Vec3b(static_cast<uint8_t>(x % 256), static_cast<uint8_t>(y % 256), 128);
  cv::circle(img, {width / 3, height / 2}, height / 6, {30, 90, 220}, cv::FILLED);
  return img;
}

cv::Mat decoded(const EyeView& eye) {
  const std::vector<uint8_t> bytes(eye.data, eye.data + eye.bytes);
  return cv::imdecode(bytes, cv::IMREAD_COLOR);
}

FrameCodecParams preview_params(int max_width_px) {
  FrameCodecParams p;
  p.preview_max_width_px = max_width_px;
  return p;
}

TEST(PreviewEncoder, BgrEyesBecomeJpegsOfTheSameSizeAndFrame) {
  // Given a 640x480 bgr8 frame and previews up to 640 px wide
  const cv::Mat left = gradient(640, 480), right = gradient(640, 480);
  auto view = view_of_images(left, right, 42, 1'000'000'123);
  ASSERT_TRUE(view.ok());
  PreviewEncoder encoder(preview_params(640));
  // When the preview is made
  const auto p = encoder.step(*view);
  // Then both eyes are JPEGs of 640x480 close to the original, with the frame's seq and stamps
  ASSERT_TRUE(p.ok()) << p.error();
  EXPECT_EQ(p->view.encoding, "jpeg");
  EXPECT_EQ(p->view.seq, 42u);
  EXPECT_EQ(p->view.stamp_ns, 1'000'000'123);
  EXPECT_EQ(p->view.left.capture_stamp_ns, view->left.capture_stamp_ns);
  EXPECT_EQ(p->source_width_px, 640u);
  EXPECT_EQ(p->source_height_px, 480u);
  for (const EyeView* eye : {&p->view.left, &p->view.right}) {
    EXPECT_EQ(eye->width_px, 640u);
    EXPECT_EQ(eye->step_bytes, 0u);
    const cv::Mat img = decoded(*eye);
    ASSERT_EQ(img.size(), cv::Size(640, 480));
    EXPECT_LT(cv::norm(img, left, cv::NORM_L1) / img.total() / 3, 6.0);
  }
  // And a small fraction of the raw bytes
  EXPECT_LT(p->view.left.bytes, left.total() * 3 / 5);
}

TEST(PreviewEncoder, WideEyesAreScaledDownAndKeepTheirSourceSize) {
  // Given 1280x720 eyes and previews up to 640 px wide
  const cv::Mat left = gradient(1280, 720);
  auto view = view_of_images(left, left, 1, 5);
  ASSERT_TRUE(view.ok());
  PreviewEncoder encoder(preview_params(640));
  // When the preview is made
  const auto p = encoder.step(*view);
  // Then the eyes are 640x360 and the source size says 1280x720 (the detections' pixels)
  ASSERT_TRUE(p.ok()) << p.error();
  EXPECT_EQ(decoded(p->view.left).size(), cv::Size(640, 360));
  EXPECT_EQ(p->view.left.width_px, 640u);
  EXPECT_EQ(p->view.left.height_px, 360u);
  EXPECT_EQ(p->source_width_px, 1280u);
  EXPECT_EQ(p->source_height_px, 720u);
}

TEST(PreviewEncoder, MonoAndYuyvEyesAreEncoded) {
  // Given a mono8 frame and a yuyv frame
  cv::Mat grey;
  cv::cvtColor(gradient(320, 240), grey, cv::COLOR_BGR2GRAY);
  auto mono = view_of_images(grey, grey, 1, 5);
  ASSERT_TRUE(mono.ok());
  std::vector<uint8_t> yuyv(320 * 240 * 2, 128);
  FrameView packed;
  packed.encoding = "yuyv";
  packed.left = {5, 320, 240, 640, yuyv.data(), yuyv.size()};
  packed.right = packed.left;
  PreviewEncoder encoder(preview_params(640));
  // When previews are made, then both decode at 320x240
  for (const FrameView* v : {&*mono, &packed}) {
    const auto p = encoder.step(*v);
    ASSERT_TRUE(p.ok()) << v->encoding << ": " << p.error();
    EXPECT_EQ(decoded(p->view.right).size(), cv::Size(320, 240)) << v->encoding;
  }
}

TEST(PreviewEncoder, BadInputIsRefusedWithTheReason) {
  const cv::Mat img = gradient(64, 48);
  auto good = view_of_images(img, img, 1, 5);
  ASSERT_TRUE(good.ok());
  PreviewEncoder encoder(preview_params(640));
  // A compressed frame (its publisher offers no preview)
  FrameView jpeg = *good;
  jpeg.encoding = "jpeg";
  auto r = encoder.step(jpeg);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("\"jpeg\""), std::string::npos) << r.error();
  // Fewer bytes than the size fields claim
  FrameView truncated = *good;
  truncated.right.bytes /= 2;
  r = encoder.step(truncated);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("right eye"), std::string::npos) << r.error();
  // Eyes of different sizes
  FrameView mismatched = *good;
  mismatched.right.width_px = 32;
  r = encoder.step(mismatched);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("differ"), std::string::npos) << r.error();
  // An odd yuyv width
  std::vector<uint8_t> yuyv(63 * 48 * 2);
  FrameView odd;
  odd.encoding = "yuyv";
  odd.left = {5, 63, 48, 126, yuyv.data(), yuyv.size()};
  odd.right = odd.left;
  r = encoder.step(odd);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("odd"), std::string::npos) << r.error();
}

TEST(PreviewParams, RangesAreChecked) {
  FrameCodecParams p;
  EXPECT_TRUE(p.validate());
  p.preview_jpeg_quality = 0;
  EXPECT_FALSE(p.validate());
  p = FrameCodecParams{};
  p.preview_max_width_px = -1;
  EXPECT_FALSE(p.validate());
  p.preview_max_width_px = 0;  // no preview
  EXPECT_TRUE(p.validate());
}

}  // namespace
}  // namespace stereoball::stereo
