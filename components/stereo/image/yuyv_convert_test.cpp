#include "stereo/image/yuyv_convert.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <random>
#include <string>
#include <vector>

namespace stereoball::stereo {
namespace {

std::vector<uint8_t> random_yuyv(int h, int step, uint32_t seed) {
  std::vector<uint8_t> v(static_cast<size_t>(step) * h);
  std::mt19937 rng(seed);
  for (auto& b : v) b = static_cast<uint8_t>(rng());
  return v;
}

cv::Mat opencv_reference(const std::vector<uint8_t>& yuyv, int w, int h, int step) {
  const cv::Mat src(h, w, CV_8UC2, const_cast<uint8_t*>(yuyv.data()), step);
  cv::Mat bgr;
  cv::cvtColor(src, bgr, cv::COLOR_YUV2BGR_YUYV);
  return bgr;
}

TEST(YuyvToBgr, GivenRandomFrameWhenConvertedThenIdenticalToOpenCv) {
  const int w = 640, h = 480;
  const auto yuyv = random_yuyv(h, 2 * w, 1);
  cv::Mat mine;
  ASSERT_TRUE(yuyv_to_bgr(yuyv, w, h, 2 * w, mine));
  const cv::Mat ref = opencv_reference(yuyv, w, h, 2 * w);
  ASSERT_EQ(mine.size(), ref.size());
  ASSERT_EQ(mine.type(), ref.type());
  EXPECT_EQ(cv::norm(mine, ref, cv::NORM_INF), 0.0);
}

TEST(YuyvToBgr, GivenEveryYuvCombinationWhenConvertedThenIdenticalToOpenCv) {
  // 256 x 256 (u, v) combinations, each with the 256 luma values spread over the row.
  const int w = 512, h = 256 * 8;
  std::vector<uint8_t> yuyv(static_cast<size_t>(w) * 2 * h);
  for (int row = 0; row < h; ++row) {
    for (int p = 0; p < w / 2; ++p) {
      uint8_t* q = &yuyv[(static_cast<size_t>(row) * w + 2 * p) * 2];
      const int uv = row * 32 + p / 8;  // 65536 combinations across the frame
      q[0] = static_cast<uint8_t>(p);
      q[1] = static_cast<uint8_t>(uv & 0xFF);
      q[2] = static_cast<uint8_t>(255 - p);
      q[3] = static_cast<uint8_t>(uv >> 8);
    }
  }
  cv::Mat mine;
  ASSERT_TRUE(yuyv_to_bgr(yuyv, w, h, 2 * w, mine));
  EXPECT_EQ(cv::norm(mine, opencv_reference(yuyv, w, h, 2 * w), cv::NORM_INF), 0.0);
}

TEST(YuyvToBgr, GivenPaddedRowsWhenConvertedThenPaddingIsIgnored) {
  const int w = 64, h = 8, step = 2 * w + 32;
  const auto yuyv = random_yuyv(h, step, 2);
  cv::Mat mine;
  ASSERT_TRUE(yuyv_to_bgr(yuyv, w, h, step, mine));
  EXPECT_EQ(cv::norm(mine, opencv_reference(yuyv, w, h, step), cv::NORM_INF), 0.0);
}

TEST(YuyvToBgr, GivenOddSizesIntoExactBufferWhenConvertedThenIdenticalAndNothingWrittenPast) {
  for (int w : {2, 14, 16, 18, 30, 70, 640}) {
    const int h = 3;
    const auto yuyv = random_yuyv(h, 2 * w, static_cast<uint32_t>(w));
    std::vector<uint8_t> dst(static_cast<size_t>(3) * w * h + 16, 0xAB);  // 16 sentinel bytes
    ASSERT_TRUE(yuyv_to_bgr_into(yuyv, w, h, 2 * w, dst.data(), 3 * w));
    const cv::Mat mine(h, w, CV_8UC3, dst.data());
    EXPECT_EQ(cv::norm(mine, opencv_reference(yuyv, w, h, 2 * w), cv::NORM_INF), 0.0) << w;
    for (size_t i = static_cast<size_t>(3) * w * h; i < dst.size(); ++i) {
      ASSERT_EQ(dst[i], 0xAB) << "byte " << i << " past the image was written, width " << w;
    }
  }
}

TEST(YuyvToBgr, GivenTruncatedFrameWhenConvertedThenErrorNamesSizes) {
  std::vector<uint8_t> yuyv(100);
  cv::Mat out;
  const Status s = yuyv_to_bgr(yuyv, 640, 480, 1280, out);
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().find("truncated"), std::string::npos);
  EXPECT_NE(s.error().find("640x480"), std::string::npos);
}

TEST(YuyvToBgr, GivenOddWidthWhenConvertedThenErrorNamesTheSize) {
  std::vector<uint8_t> yuyv(1000);
  cv::Mat out;
  const Status s = yuyv_to_bgr(yuyv, 7, 2, 14, out);
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().find("7x2"), std::string::npos) << s.error();
}

}  // namespace
}  // namespace stereoball::stereo
