#include "viewer/bridge/eye_encoder.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace stereoball::viewer {
namespace {

stereoball_msg_EyeImage eye(std::vector<uint8_t>& bytes, uint32_t w, uint32_t h, uint32_t step) {
  stereoball_msg_EyeImage e{};
  e.width_px = w;
  e.height_px = h;
  e.step_bytes = step;
  e.data._buffer = bytes.data();
  e.data._length = static_cast<uint32_t>(bytes.size());
  return e;
}

TEST(EyeEncoder, Bgr8BecomesAJpegOfTheSameImage) {
  // Given a 64x48 BGR image, left half red, right half blue
  cv::Mat img(48, 64, CV_8UC3, cv::Scalar(255, 0, 0));
  img(cv::Rect(0, 0, 32, 48)).setTo(cv::Scalar(0, 0, 255));
  std::vector<uint8_t> bytes(img.data, img.data + img.total() * 3);
  const auto jpeg = EyeEncoder({}).encode(eye(bytes, 64, 48, 64 * 3), "bgr8");
  ASSERT_TRUE(jpeg) << jpeg.error();
  const cv::Mat back = cv::imdecode(jpeg->bytes, cv::IMREAD_COLOR);
  ASSERT_EQ(back.size(), cv::Size(64, 48));
  EXPECT_GT(back.at<cv::Vec3b>(24, 8)[2], 200);   // red on the left
  EXPECT_GT(back.at<cv::Vec3b>(24, 56)[0], 200);  // blue on the right
}

TEST(EyeEncoder, WideImagesAreScaledDownToMaxWidth) {
  std::vector<uint8_t> bytes(1280 * 960, 128);
  EyeEncoderParams p;
  p.max_width_px = 640;
  const auto jpeg = EyeEncoder(p).encode(eye(bytes, 1280, 960, 1280), "mono8");
  ASSERT_TRUE(jpeg) << jpeg.error();
  EXPECT_EQ(jpeg->width_px, 640u);
  EXPECT_EQ(jpeg->height_px, 480u);
}

TEST(EyeEncoder, JpegPassesThroughUnchanged) {
  std::vector<uint8_t> src;
  cv::imencode(".jpg", cv::Mat(8, 8, CV_8UC3, cv::Scalar(1, 2, 3)), src);
  const auto jpeg = EyeEncoder({}).encode(eye(src, 8, 8, 0), "jpeg");
  ASSERT_TRUE(jpeg);
  EXPECT_EQ(jpeg->bytes, src);
}

TEST(EyeEncoder, BadInputIsNamed) {
  std::vector<uint8_t> short_data(100);
  EXPECT_NE(EyeEncoder({}).encode(eye(short_data, 64, 48, 192), "bgr8").error().find("truncated"),
            std::string::npos);
  EXPECT_NE(EyeEncoder({}).encode(eye(short_data, 64, 48, 10), "bgr8").error().find("step_bytes"),
            std::string::npos);
  EXPECT_NE(EyeEncoder({}).encode(eye(short_data, 99999, 1, 99999), "mono8").error().find("8192"),
            std::string::npos);
  EXPECT_NE(EyeEncoder({}).encode(eye(short_data, 8, 8, 0), "jpeg").error().find("JPEG marker"),
            std::string::npos);
  EXPECT_NE(EyeEncoder({}).encode(eye(short_data, 8, 8, 0), "png").error().find("png"),
            std::string::npos);
  EXPECT_NE(EyeEncoder({}).encode(eye(short_data, 8, 8, 8), "rgb16").error().find("rgb16"),
            std::string::npos);
}

}  // namespace
}  // namespace stereoball::viewer
