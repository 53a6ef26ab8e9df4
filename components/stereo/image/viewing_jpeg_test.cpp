// The viewing JPEG encoder: the picture comes back decodable at the size asked for, colour
// and grey, and what it cannot encode is refused with a message.

#include "stereo/image/viewing_jpeg.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "stereo/image/image_decode.hpp"

namespace stereoball::stereo {
namespace {

cv::Mat disc(int width, int height, int type) {
  cv::Mat img(height, width, type, cv::Scalar::all(40));
  cv::circle(img, {width / 2, height / 2}, height / 4, cv::Scalar(30, 120, 220), cv::FILLED);
  return img;
}

TEST(ViewingJpeg, GivenAWideColourImageThenItIsScaledToTheWidthAndDecodesAtThatSize) {
  ViewingJpegEncoder encoder;
  const auto jpeg = encoder.encode(disc(640, 480, CV_8UC3), 320, 75);
  ASSERT_TRUE(jpeg.ok()) << jpeg.error();
  EXPECT_EQ(jpeg->width_px, 320);
  EXPECT_EQ(jpeg->height_px, 240);
  const auto header = read_image_header(jpeg->bytes);
  ASSERT_TRUE(header.ok()) << header.error();
  EXPECT_EQ(header->codec, ImageCodec::kJpeg);
  EXPECT_EQ(header->width_px, 320);
  EXPECT_EQ(header->height_px, 240);
}

TEST(ViewingJpeg, GivenANarrowGreyImageOrNoLimitThenItKeepsItsSize) {
  ViewingJpegEncoder encoder;
  const auto grey = encoder.encode(disc(200, 100, CV_8UC1), 320, 75);
  ASSERT_TRUE(grey.ok()) << grey.error();
  EXPECT_EQ(grey->width_px, 200);
  const auto unlimited = encoder.encode(disc(640, 480, CV_8UC3), 0, 75);
  ASSERT_TRUE(unlimited.ok()) << unlimited.error();
  EXPECT_EQ(unlimited->width_px, 640);
}

TEST(ViewingJpeg, GivenAnEmptyOrFloatImageThenTheErrorSaysWhatItNeeds) {
  ViewingJpegEncoder encoder;
  const auto empty = encoder.encode(cv::Mat(), 320, 75);
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.error().find("8-bit BGR or grey"), std::string::npos) << empty.error();
  EXPECT_FALSE(encoder.encode(cv::Mat(10, 10, CV_32FC3), 320, 75).ok());
}

}  // namespace
}  // namespace stereoball::stereo
