#include "camera_server/core/pixel_convert.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <vector>

namespace stereoball::camera_server {
namespace {

TEST(MjpegToBgr, GivenJpegEncodedByOpenCvWhenDecodedThenMatchesImdecode) {
  cv::Mat img(48, 64, CV_8UC3);
  cv::randu(img, 0, 255);
  std::vector<uint8_t> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", img, jpeg));
  cv::Mat mine;
  ASSERT_TRUE(mjpeg_to_bgr(jpeg, 64, 48, mine).ok());
  const cv::Mat ref = cv::imdecode(jpeg, cv::IMREAD_COLOR);
  EXPECT_EQ(cv::norm(mine, ref, cv::NORM_INF), 0.0);
}

TEST(MjpegToBgr, GivenWrongSizeWhenDecodedThenErrorNamesBothSizes) {
  cv::Mat img(48, 64, CV_8UC3, cv::Scalar(1, 2, 3));
  std::vector<uint8_t> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", img, jpeg));
  cv::Mat out;
  const Status s = mjpeg_to_bgr(jpeg, 640, 480, out);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().find("64x48"), std::string::npos);
  EXPECT_NE(s.error().find("640x480"), std::string::npos);
}

TEST(MjpegToBgr, GivenGarbageOrTruncatedDataWhenDecodedThenErrorNotCrash) {
  cv::Mat out;
  std::vector<uint8_t> garbage{1, 2, 3, 4, 5, 6};
  EXPECT_FALSE(mjpeg_to_bgr(garbage, 0, 0, out).ok());
  std::vector<uint8_t> header_only{0xFF, 0xD8, 0xFF, 0xE0, 0, 0};
  const Status s = mjpeg_to_bgr(header_only, 0, 0, out);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().find("could not be decoded"), std::string::npos);
}

}  // namespace
}  // namespace stereoball::camera_server
