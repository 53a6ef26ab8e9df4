// Epipolar check on a real rectified pair (Middlebury Aloe, from OpenCV's samples).

#include "stereo/core/row_check.hpp"
#include "stereo/core/epipolar.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace stereoball::stereo {
namespace {

const std::string kRowCheckDir = std::string(SB_SHARED_DATA_DIR) + "/opencv-samples/";

class AloeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    left_ = cv::imread(kRowCheckDir + "aloeL.jpg", cv::IMREAD_GRAYSCALE);
    right_ = cv::imread(kRowCheckDir + "aloeR.jpg", cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(left_.empty());
    ASSERT_FALSE(right_.empty());
  }
  // Fraction of matches the paper's 2 px epipolar check accepts.
  static double accepted_fraction(const std::vector<RowMatch>& matches) {
    const EpipolarCheck check(EpipolarParams{});
    std::size_t ok = 0;
    for (const RowMatch& m : matches) ok += check.check(m.left_px, m.right_px).accepted ? 1 : 0;
    return matches.empty() ? 0.0 : static_cast<double>(ok) / static_cast<double>(matches.size());
  }
  cv::Mat left_, right_;
};

TEST_F(AloeTest, GivenRectifiedRealPairWhenFeaturesMatchedThenRowsAgreeAndCheckAccepts) {
  // Given the real rectified Aloe pair, When features are matched in a 2D window
  const auto matches = match_rows(left_, right_, RowCheckParams{});
  const RowResidualStats s = summarize_rows(matches);
  // Then many matches are found, on the same rows, and the 2 px check accepts them
  ASSERT_GE(s.count, 50u);
  EXPECT_LT(s.median_abs_px, 0.5);
  EXPECT_GT(accepted_fraction(matches), 0.95);
}

TEST_F(AloeTest, GivenRightImageShifted5RowsWhenMatchedThenResidualShowsShiftAndCheckRejects) {
  // Given the right image moved 5 rows down (a badly rectified pair)
  cv::Mat shifted;
  const cv::Matx23d shift(1, 0, 0, 0, 1, 5);
  cv::warpAffine(right_, shifted, shift, right_.size());
  // When matched
  const auto matches = match_rows(left_, shifted, RowCheckParams{});
  const RowResidualStats s = summarize_rows(matches);
  // Then the residual reports the shift and the epipolar check rejects most pairs
  ASSERT_GE(s.count, 50u);
  EXPECT_NEAR(s.mean_signed_px, 5.0, 0.5);
  EXPECT_LT(accepted_fraction(matches), 0.1);
}

TEST(RowCheck, GivenMismatchedSizesWhenMatchedThenNoMatches) {
  EXPECT_TRUE(match_rows(cv::Mat(100, 100, CV_8U), cv::Mat(90, 100, CV_8U), {}).empty());
  EXPECT_EQ(summarize_rows({}).count, 0u);
  EXPECT_TRUE(RowCheckParams{}.validate().ok());
  RowCheckParams p;
  p.min_score = 0.0;
  EXPECT_EQ(p.validate().error().rfind("min_score", 0), 0u);
}

}  // namespace
}  // namespace stereoball::stereo
