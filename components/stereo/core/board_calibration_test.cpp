// Real-data acceptance: stereo calibration on OpenCV's 13 sample pairs
// (640x480, 9x6 inner corners; square size unknown, 25 mm assumed).

#include "stereo/core/board_calibration.hpp"

#include "stereo/core/rectifier.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <string>

namespace stereoball::stereo {
namespace {

const std::string kDir = std::string(SB_SHARED_DATA_DIR) + "/opencv-samples/";
const int kIds[] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 12, 13, 14};

std::string name(const char* side, int id) {
  return kDir + side + (id < 10 ? "0" : "") + std::to_string(id) + ".jpg";
}

// Corners of every sample pair where the board is found in both eyes.
const std::vector<PairCorners>& sample_corners() {
  static const std::vector<PairCorners> pairs = [] {
    std::vector<PairCorners> out;
    const BoardCalibrationParams params;
    for (int id : kIds) {
      const cv::Mat l = cv::imread(name("left", id), cv::IMREAD_GRAYSCALE);
      const cv::Mat r = cv::imread(name("right", id), cv::IMREAD_GRAYSCALE);
      const auto cl = find_board_corners(l, params);
      const auto cr = find_board_corners(r, params);
      if (!cl || !cr) continue;
      PairCorners p{std::to_string(id), *cl, *cr};
      align_corner_order(p.left_px, p.right_px);
      out.push_back(std::move(p));
    }
    return out;
  }();
  return pairs;
}

TEST(RealCalibration, GivenOpenCvSamplePairsWhenCalibratedThenRmsAndRowErrorTargetsMet) {
  // Given the corners of the real sample pairs
  const auto& pairs = sample_corners();
  ASSERT_GE(pairs.size(), 10u) << "board not found in enough sample pairs";
  // When calibrated with a 25 mm square
  const auto result = calibrate_stereo(pairs, cv::Size(640, 480), BoardCalibrationParams{});
  // Then the RMS reprojection error and the rectified row error meet the targets
  ASSERT_TRUE(result.ok()) << result.error();
  const StereoCalibration& c = result->calibration;
  EXPECT_LT(c.rms_px, 0.5);
  EXPECT_LT(result->mean_rectified_row_error_px, 0.25);
  EXPECT_EQ(c.per_pair_rms_px.size(), pairs.size());
  for (double e : c.per_pair_rms_px) EXPECT_LT(e, 1.0);
  // and the rig looks like the sample's: right camera to the right, a few cm apart
  EXPECT_LT(c.t[0], 0.0);
  EXPECT_GT(cv::norm(c.t), 0.01);
  EXPECT_LT(cv::norm(c.t), 0.5);
  EXPECT_EQ(validate_calibration(c), std::nullopt);
}

TEST(RealCalibration, GivenCalibrationWhenRealPairLutRectifiedThenBoardCornersShareRows) {
  // Given the calibration of the real sample pairs
  const auto result =
      calibrate_stereo(sample_corners(), cv::Size(640, 480), BoardCalibrationParams{});
  ASSERT_TRUE(result.ok()) << result.error();
  const Rectifier rect = Rectifier::create(result->calibration).value();
  // When a real pair goes through the fixed-point LUT and the board is found again
  cv::Mat l, r;
  ASSERT_EQ(rect.rectify(cv::imread(name("left", 3), cv::IMREAD_GRAYSCALE),
                         cv::imread(name("right", 3), cv::IMREAD_GRAYSCALE), l, r),
            std::nullopt);
  const auto cl = find_board_corners(l, BoardCalibrationParams{});
  auto cr = find_board_corners(r, BoardCalibrationParams{});
  ASSERT_TRUE(cl && cr);
  align_corner_order(*cl, *cr);
  // Then corresponding corners lie on the same rows (whole-image path, not just points)
  double sum = 0.0;
  for (std::size_t i = 0; i < cl->size(); ++i) sum += std::abs((*cl)[i].y - (*cr)[i].y);
  EXPECT_LT(sum / static_cast<double>(cl->size()), 0.3);
}

TEST(RealCalibration, GivenTooFewPairsWhenCalibratedThenErrorNamesMinPairs) {
  const auto& all = sample_corners();
  ASSERT_GE(all.size(), 3u);
  const std::vector<PairCorners> few(all.begin(), all.begin() + 3);
  const auto result = calibrate_stereo(few, cv::Size(640, 480), BoardCalibrationParams{});
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().find("min_pairs"), std::string::npos) << result.error();
}

TEST(BoardCorners, GivenImageWithoutBoardWhenSearchedThenNotFound) {
  const cv::Mat aloe = cv::imread(kDir + "aloeL.jpg", cv::IMREAD_COLOR);
  ASSERT_FALSE(aloe.empty());
  EXPECT_FALSE(find_board_corners(aloe, BoardCalibrationParams{}).has_value());
  EXPECT_FALSE(find_board_corners(cv::Mat(), BoardCalibrationParams{}).has_value());
}

TEST(BoardCorners, GivenReversedRightCornersWhenAlignedThenOrderRestored) {
  // Given a pair whose right corners came out in reverse board order
  const auto& p = sample_corners().front();
  std::vector<cv::Point2f> right(p.right_px.rbegin(), p.right_px.rend());
  // When aligned, then they are flipped back; an aligned pair is left alone
  EXPECT_TRUE(align_corner_order(p.left_px, right));
  EXPECT_EQ(right, p.right_px);
  EXPECT_FALSE(align_corner_order(p.left_px, right));
}

TEST(BoardCalibrationParams, GivenBadValuesWhenValidatedThenFieldNamed) {
  BoardCalibrationParams p;
  EXPECT_EQ(p.validate(), std::nullopt);
  p.square_m = 0;
  EXPECT_EQ(p.validate()->rfind("square_m", 0), 0u);
  p = {};
  p.min_pairs = 1;
  EXPECT_EQ(p.validate()->rfind("min_pairs", 0), 0u);
  p = {};
  p.inner_corners = {1, 6};
  EXPECT_EQ(p.validate()->rfind("inner_corners", 0), 0u);
}

}  // namespace
}  // namespace stereoball::stereo
