#include "stereo/frame/eye_pixels.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <cstdint>
#include <vector>

namespace stereoball::stereo {
namespace {

TEST(EyePixels, GivenRawEyesThenBgrAndMonoAreViewedAndYuyvIsConvertedAsOpenCvDoes) {
  // Given a bgr8 eye and a yuyv eye of random bytes in rows padded to 140 bytes
  cv::Mat bgr(48, 64, CV_8UC3), yuyv(48, 70, CV_8UC2);
  cv::randu(bgr, cv::Scalar::all(0), cv::Scalar::all(256));
  cv::randu(yuyv, cv::Scalar::all(0), cv::Scalar::all(256));
  const EyeView bgr_eye = eye_view(bgr, 1);
  const EyeView yuyv_eye{1, 64, 48, 140, yuyv.data, yuyv.total() * 2};
  cv::Mat converted;
  // When their pixels are asked for
  const auto bgr_pixels = eye_pixels(bgr_eye, "bgr8", converted);
  const auto yuyv_pixels = eye_pixels(yuyv_eye, "yuyv", converted);
  // Then bgr8 is the eye's own memory and yuyv is OpenCV's conversion bit for bit
  ASSERT_TRUE(bgr_pixels) << bgr_pixels.error();
  EXPECT_EQ(bgr_pixels->data, bgr.data);
  ASSERT_TRUE(yuyv_pixels) << yuyv_pixels.error();
  cv::Mat want;
  cv::cvtColor(yuyv(cv::Rect(0, 0, 64, 48)), want, cv::COLOR_YUV2BGR_YUYV);
  ASSERT_EQ(yuyv_pixels->size(), want.size());
  EXPECT_EQ(cv::norm(*yuyv_pixels, want, cv::NORM_INF), 0.0);
  EXPECT_EQ(yuyv_pixels->data, converted.data);
}

TEST(EyePixels, GivenEyesWithoutRawPixelsThenTheErrorNamesTheProblem) {
  std::vector<uint8_t> bytes(64 * 48 * 2);
  const EyeView eye{1, 64, 48, 128, bytes.data(), bytes.size()};
  cv::Mat converted;
  EXPECT_NE(eye_pixels(eye, "jpeg", converted).error().find("\"jpeg\""), std::string::npos);
  EyeView odd = eye;
  odd.width_px = 63;
  EXPECT_NE(eye_pixels(odd, "yuyv", converted).error().find("odd"), std::string::npos);
  EyeView truncated = eye;
  truncated.bytes = bytes.size() / 2;
  EXPECT_NE(eye_pixels(truncated, "yuyv", converted).error().find("bytes"), std::string::npos);
}

}  // namespace
}  // namespace stereoball::stereo
