// Scaling a real rig's calibration: the real basketball rig (2304x1296) and one of its pairs.

#include <gtest/gtest.h>

#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "stereo/core/calibration_scaling.hpp"
#include "stereo/core/rectifier.hpp"
#include "stereo/io/calibration_file.hpp"

namespace stereoball::stereo {
namespace {

const std::string kRig = std::string(SB_SHARED_DATA_DIR) + "/real-stereo-basketball/";

cv::Mat grey(const std::string& path) {
  return cv::imread(path, cv::IMREAD_GRAYSCALE);
}

cv::Mat halved(const cv::Mat& image) {
  cv::Mat out;
  cv::resize(image, out, cv::Size(image.cols / 2, image.rows / 2), 0, 0, cv::INTER_AREA);
  return out;
}

// Sub-pixel shift between two images of the same scene (phase correlation), pixels.
cv::Point2d shift_between(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat fa, fb;
  a.convertTo(fa, CV_64F);
  b.convertTo(fb, CV_64F);
  return cv::phaseCorrelate(fa, fb);
}

TEST(ScaleCalibrationRealRig, GivenARealPairWhenHalvedThenRectifyingItMatchesTheHalvedRectified) {
  // Given the real rig's calibration and its pair 10 (ball in the middle of a room)
  const auto calib = load_calibration(kRig + "calibration/rig_2304x1296.yaml");
  ASSERT_TRUE(calib.ok()) << calib.error();
  const cv::Mat left = grey(kRig + "left/left_10.jpg"), right = grey(kRig + "right/right_10.jpg");
  ASSERT_FALSE(left.empty() || right.empty());
  const Rectifier full = Rectifier::create(*calib).value();
  cv::Mat left_full, right_full;
  ASSERT_TRUE(full.rectify(left, right, left_full, right_full).ok());
  // When the raw pair and the calibration are halved and the halves rectified
  const auto half_calib = scale_calibration(*calib, {1152, 648});
  ASSERT_TRUE(half_calib.ok()) << half_calib.error();
  const Rectifier half = Rectifier::create(*half_calib).value();
  cv::Mat left_half, right_half;
  ASSERT_TRUE(half.rectify(halved(left), halved(right), left_half, right_half).ok());
  // Then each eye equals the halved full-size rectified eye within a tenth of a pixel of shift
  // and a few grey levels, while the unscaled calibration cannot rectify the halves at all
  for (int eye = 0; eye < 2; ++eye) {
    const cv::Mat expected = halved(eye == 0 ? left_full : right_full);
    const cv::Mat& got = eye == 0 ? left_half : right_half;
    ASSERT_EQ(got.size(), expected.size());
    const cv::Point2d d = shift_between(got, expected);
    cv::Mat diff;
    cv::absdiff(got, expected, diff);
    const double mean_diff = cv::mean(diff)[0];
    std::printf("eye %d: shift (%.3f, %.3f) px, mean |diff| %.2f DN\n", eye, d.x, d.y, mean_diff);
    EXPECT_LT(std::abs(d.x), 0.1);
    EXPECT_LT(std::abs(d.y), 0.1);
    EXPECT_LT(mean_diff, 4.0);
  }
  cv::Mat unused;
  EXPECT_FALSE(full.rectify_eye(Eye::kLeft, halved(left), unused).ok());
}

}  // namespace
}  // namespace stereoball::stereo
