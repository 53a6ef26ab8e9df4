// Image measures of `stereoball doctor` on real pairs: OpenCV's chessboard rig (raw pairs and
// its calibration). Nothing here was tuned on these pairs beyond what the README states.

#include "image_measures.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdio>

#include "stereo/io/calibration_file.hpp"

namespace stereoball::doctor {
namespace {

const std::string kDir = std::string(SB_SHARED_DATA_DIR) + "/opencv-samples/";
const std::string kCalibration =
    std::string(SB_SOURCE_DIR) + "/config/calibration/opencv_samples_stereo.yaml";

cv::Mat grey(const std::string& name) {
  return cv::imread(kDir + name, cv::IMREAD_GRAYSCALE);
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

class RealPairs : public ::testing::Test {
 protected:
  void SetUp() override {
    auto calib = stereo::load_calibration(kCalibration);
    ASSERT_TRUE(calib.ok()) << calib.error();
    auto rect = stereo::Rectifier::create(*calib);
    ASSERT_TRUE(rect.ok()) << rect.error();
    rectifier_ = std::make_unique<stereo::Rectifier>(std::move(*rect));
  }
  std::unique_ptr<stereo::Rectifier> rectifier_;
};

TEST_F(RealPairs, GivenPairsInTheirOrderThenMostDisparitiesArePositiveAndRowsAgree) {
  // Given three real raw pairs in the calibration's order
  StereoMeasures m;
  for (const char* id : {"01", "06", "12"}) {
    const cv::Mat l = grey(std::string("left") + id + ".jpg"),
                  r = grey(std::string("right") + id + ".jpg");
    ASSERT_FALSE(l.empty() || r.empty()) << id;
    // When measured as the doctor measures live pairs
    add_pair(m, rectifier_.get(), l, r, false);
  }
  std::printf("as given: %zu positive, %zu negative, %zu row matches, median |dy| %.3f px\n",
              m.positive, m.negative, m.abs_row_px.size(), median(m.abs_row_px));
  // Then the pairs were rectified and the positive disparities win clearly
  EXPECT_EQ(m.stereo_pairs, 3);
  EXPECT_TRUE(m.stereo_error.empty()) << m.stereo_error;
  EXPECT_GE(m.positive, 20u);
  EXPECT_GT(m.positive, 2 * m.negative);
  // And the rectified rows agree within a pixel (the rig's calibration fits its pairs)
  ASSERT_GE(m.abs_row_px.size(), 20u);
  EXPECT_LT(median(m.abs_row_px), 1.0);
}

TEST_F(RealPairs, GivenSwappedEyesThenMostDisparitiesAreNegative) {
  // Given the same pairs with left and right exchanged (cameras plugged the other way)
  StereoMeasures m;
  for (const char* id : {"01", "06", "12"}) {
    add_pair(m, rectifier_.get(), grey(std::string("right") + id + ".jpg"),
             grey(std::string("left") + id + ".jpg"), false);
  }
  std::printf("swapped: %zu positive, %zu negative\n", m.positive, m.negative);
  // Then the negative disparities win clearly
  EXPECT_GE(m.negative, 20u);
  EXPECT_GT(m.negative, 2 * m.positive);
}

TEST_F(RealPairs, GivenAFrameOfAnotherSizeThenTheStereoPartSaysWhyAndExposureIsStillMeasured) {
  // Given a pair at half the calibration's size
  cv::Mat l, r;
  cv::resize(grey("left01.jpg"), l, {320, 240});
  cv::resize(grey("right01.jpg"), r, {320, 240});
  StereoMeasures m;
  // When measured
  add_pair(m, rectifier_.get(), l, r, false);
  // Then it is not rectified, the error says so, and the eyes are still measured
  EXPECT_EQ(m.pairs, 1);
  EXPECT_EQ(m.stereo_pairs, 0);
  EXPECT_NE(m.stereo_error.find("cannot rectify"), std::string::npos) << m.stereo_error;
  EXPECT_GT(m.left.mean, 10);
}

TEST(EyeImage, GivenBlackBrightAndBlurredImagesThenTheMeasuresTellThemApart) {
  // Given a real image, a black one, a saturated one and a blurred copy
  const cv::Mat real = grey("left01.jpg");
  ASSERT_FALSE(real.empty());
  cv::Mat blurred;
  cv::GaussianBlur(real, blurred, {0, 0}, 4.0);
  const EyeImageStats s = measure_eye(real);
  const EyeImageStats black = measure_eye(cv::Mat(480, 640, CV_8UC1, cv::Scalar(0)));
  const EyeImageStats white = measure_eye(cv::Mat(480, 640, CV_8UC3, cv::Scalar(255, 255, 255)));
  const EyeImageStats soft = measure_eye(blurred);
  // Then mean and clipping follow the pixels and the blur lowers the Laplacian's variance
  EXPECT_GT(s.mean, 40);
  EXPECT_LT(s.mean, 215);
  EXPECT_DOUBLE_EQ(black.mean, 0);
  EXPECT_DOUBLE_EQ(black.dark_fraction, 1.0);
  EXPECT_DOUBLE_EQ(white.bright_fraction, 1.0);
  EXPECT_LT(soft.laplacian_var, s.laplacian_var / 10);
  Limits limits;
  EXPECT_GT(s.laplacian_var, limits.blur_warn_laplacian_var);
  EXPECT_LT(soft.laplacian_var, limits.blur_warn_laplacian_var);
}

}  // namespace
}  // namespace stereoball::doctor
