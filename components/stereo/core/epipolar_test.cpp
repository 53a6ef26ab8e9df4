#include "stereo/core/epipolar.hpp"

#include "stereo/core/rectifier.hpp"
#include "stereo/core/synthetic_rig.hpp"

#include <gtest/gtest.h>

namespace stereoball::stereo {
namespace {

TEST(EpipolarCheck, GivenDefaultToleranceWhenRowsDiffer2_1ThenRejected) {
  // Given the paper's 2 px tolerance
  const EpipolarCheck check(EpipolarParams{});
  // When the right centre is 2.1 px below the left one
  const EpipolarMatch m = check.check({300.0, 200.0}, {280.0, 202.1});
  // Then the pair is rejected and the residual reported
  EXPECT_FALSE(m.accepted);
  EXPECT_NEAR(m.row_residual_px, 2.1, 1e-9);
}

TEST(EpipolarCheck, GivenDefaultToleranceWhenRowsDiffer1_9ThenAcceptedWithAveragedRow) {
  const EpipolarCheck check(EpipolarParams{});
  // When the right centre is 1.9 px above the left one
  const EpipolarMatch m = check.check({300.0, 200.0}, {280.0, 198.1});
  // Then it is accepted and the row is the average of both
  EXPECT_TRUE(m.accepted);
  EXPECT_NEAR(m.row_residual_px, 1.9, 1e-9);
  EXPECT_NEAR(m.row_px, 199.05, 1e-9);
  EXPECT_EQ(m.x_left_px, 300.0);
  EXPECT_EQ(m.x_right_px, 280.0);
}

TEST(EpipolarCheck, GivenRealRigWhenRightCentreOffsetThenToleranceAppliesInRectifiedRows) {
  // Given a ball centre projected into the raw images of the synthetic rig, point-rectified
  const SyntheticRig rig = default_synthetic_rig();
  const Rectifier rect = Rectifier::create(rig.calibration()).value();
  const cv::Point3d p(0.3, 0.15, 1.2);
  const cv::Point2d l = rect.rectify_point(Eye::kLeft, rig.project_left(p));
  const cv::Point2d r = rect.rectify_point(Eye::kRight, rig.project_right(p));
  const EpipolarCheck check(EpipolarParams{});
  // When the right centre is moved 1.9 / 2.1 rectified rows away
  // Then only the 1.9 px offset passes
  EXPECT_TRUE(check.check(l, r).accepted);
  EXPECT_TRUE(check.check(l, r + cv::Point2d(0, 1.9)).accepted);
  EXPECT_FALSE(check.check(l, r + cv::Point2d(0, 2.1)).accepted);
  EXPECT_FALSE(check.check(l, r - cv::Point2d(0, 2.1)).accepted);
}

TEST(EpipolarCheck, GivenConfiguredToleranceWhenCheckedThenItIsUsed) {
  const EpipolarCheck check(EpipolarParams{.max_row_diff_px = 0.5});
  EXPECT_TRUE(check.check({10, 10}, {5, 10.4}).accepted);
  EXPECT_FALSE(check.check({10, 10}, {5, 10.6}).accepted);
}

TEST(EpipolarParams, GivenNegativeOrNanToleranceWhenValidatedThenFieldNamed) {
  EXPECT_TRUE(EpipolarParams{}.validate().ok());
  const auto neg = EpipolarParams{.max_row_diff_px = -1.0}.validate();
  ASSERT_FALSE(neg.ok());
  EXPECT_EQ(neg.error().rfind("max_row_diff_px", 0), 0u);
  EXPECT_FALSE(EpipolarParams{.max_row_diff_px = std::nan("")}.validate().ok());
}

TEST(EpipolarCheck, GivenCandidatesWhenBestPairThenClosestRowWithPositiveDisparity) {
  // Given two left and three right candidates
  const EpipolarCheck check(EpipolarParams{});
  const std::vector<cv::Point2d> left{{300, 100}, {400, 250}};
  // right[0]: same row as left[1] but to its right (negative disparity)
  // right[1]: 1.5 px off left[0]; right[2]: 0.3 px off left[1]
  const std::vector<cv::Point2d> right{{420, 250}, {280, 101.5}, {370, 250.3}};
  // When the best pair is chosen
  const auto best = check.best_pair(left, right);
  // Then it is left[1] with right[2]
  ASSERT_TRUE(best.has_value());
  EXPECT_EQ(best->left_index, 1u);
  EXPECT_EQ(best->right_index, 2u);
  EXPECT_NEAR(best->match.row_px, 250.15, 1e-9);
}

TEST(EpipolarCheck, GivenNoPairWithinToleranceWhenBestPairThenNone) {
  const EpipolarCheck check(EpipolarParams{});
  EXPECT_FALSE(check.best_pair({{300, 100}}, {{280, 110}}).has_value());
  EXPECT_FALSE(check.best_pair({}, {{280, 100}}).has_value());
}

}  // namespace
}  // namespace stereoball::stereo
