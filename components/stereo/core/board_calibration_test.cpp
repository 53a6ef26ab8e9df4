// Real-data acceptance: stereo calibration on OpenCV's 13 sample pairs
// (640x480, 9x6 inner corners; square size unknown, 25 mm assumed).

#include "stereo/core/board_calibration.hpp"

#include "stereo/core/pair_error.hpp"
#include "stereo/core/rectifier.hpp"

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cstdio>
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
  EXPECT_TRUE(validate_calibration(c).ok());
}

const BoardCalibrationResult& sample_calibration() {
  static const BoardCalibrationResult result =
      calibrate_stereo(sample_corners(), cv::Size(640, 480), BoardCalibrationParams{}).value();
  return result;
}

// An unsynchronised rig: the right shot of a pair is taken after the board moved by move_m
// (right camera frame). Made from the real corners: the right board pose is fitted, moved and
// reprojected, and the real residual of each corner (its noise) is added back.
PairCorners desynchronise(const PairCorners& pair, const cv::Vec3d& move_m) {
  const StereoCalibration& c = sample_calibration().calibration;
  const auto board = board_points_m(BoardCalibrationParams{});
  cv::Vec3d rvec, tvec;
  cv::solvePnP(board, pair.right_px, cv::Mat(c.k2), cv::Mat(c.d2, true), rvec, tvec);
  std::vector<cv::Point2f> fitted, moved;
  cv::projectPoints(board, rvec, tvec, cv::Mat(c.k2), cv::Mat(c.d2, true), fitted);
  cv::projectPoints(board, rvec, tvec + move_m, cv::Mat(c.k2), cv::Mat(c.d2, true), moved);
  PairCorners out = pair;
  out.name += " (moved)";
  for (std::size_t i = 0; i < moved.size(); ++i)
    out.right_px[i] = moved[i] + (pair.right_px[i] - fitted[i]);
  return out;
}

TEST(RealCalibration, GivenConsistentSamplePairsWhenCalibratedThenNoPairDropped) {
  // Given the real pairs (a synchronised rig), When calibrated with outlier dropping on
  const BoardCalibrationResult& r = sample_calibration();
  // Then every pair is kept and the figures are those of all pairs (0.215 px before dropping
  // existed)
  EXPECT_TRUE(r.dropped.empty()) << r.dropped.front().reason;
  EXPECT_EQ(r.pair_names.size(), sample_corners().size());
  EXPECT_DOUBLE_EQ(r.calibration.rms_px, r.all_pairs_rms_px);
  EXPECT_LT(r.calibration.rms_px, 0.22);
}

TEST(RealCalibration, GivenPairWhenErrorMeasuredAgainstCalibrationThenSmallUnlessBoardMoved) {
  // Given the calibration of the real pairs and one of its pairs
  const StereoCalibration& c = sample_calibration().calibration;
  const PairCorners& pair = sample_corners()[4];
  const auto board = board_points_m(BoardCalibrationParams{});
  // When its error is measured as it is and with the board moved 3 mm along x (depth
  // changes) or y (rows change) in the right view
  const PairError same = stereo_pair_error(c, board, pair.left_px, pair.right_px);
  const PairCorners along_x = desynchronise(pair, {0.003, 0, 0});
  const PairCorners along_y = desynchronise(pair, {0, 0.003, 0});
  const PairError ex = stereo_pair_error(c, board, along_x.left_px, along_x.right_px);
  const PairError ey = stereo_pair_error(c, board, along_y.left_px, along_y.right_px);
  // Then the real pair fits as well as it did in the calibration, the moved ones do not
  EXPECT_LT(same.rms_px, 0.4);
  EXPECT_LT(same.mean_row_error_px, 0.3);
  EXPECT_GT(ex.rms_px, 3 * same.rms_px);
  EXPECT_GT(ey.rms_px, 3 * same.rms_px);
  EXPECT_GT(ey.mean_row_error_px, 1.0);  // a vertical move shows in the rows
  EXPECT_LT(ex.mean_row_error_px, 0.5);  // a horizontal one only in depth
}

TEST(RealCalibration, GivenUnsynchronisedPairsWhenCalibratedThenMovedPairsDroppedAndTargetsMet) {
  // Given the real pairs with the board moved by a few mm in four right views
  std::vector<PairCorners> pairs = sample_corners();
  ASSERT_GE(pairs.size(), 12u);
  const std::vector<std::pair<std::size_t, cv::Vec3d>> moves = {
      {1, {0.004, 0, 0}}, {5, {0, 0.003, 0}}, {8, {0.002, -0.002, 0.004}}, {11, {-0.003, 0, 0}}};
  for (const auto& [i, m] : moves) pairs[i] = desynchronise(pairs[i], m);
  // When calibrated
  const auto result = calibrate_stereo(pairs, cv::Size(640, 480), BoardCalibrationParams{});
  // Then exactly the moved pairs are dropped, each with its reason, and the calibration of
  // the rest meets the targets where the one of every pair did not
  ASSERT_TRUE(result.ok()) << result.error();
  const BoardCalibrationResult& r = result.value();
  std::vector<std::string> dropped;
  for (const DroppedPair& d : r.dropped) {
    dropped.push_back(d.name);
    EXPECT_NE(d.reason.find("board moved"), std::string::npos) << d.reason;
    EXPECT_GT(d.error_px, 3 * d.rest_median_px);
  }
  std::sort(dropped.begin(), dropped.end());
  std::vector<std::string> moved;
  for (const auto& [i, m] : moves) moved.push_back(pairs[i].name);
  std::sort(moved.begin(), moved.end());
  EXPECT_EQ(dropped, moved);
  std::printf(
      "desynchronised OpenCV pairs: RMS %.3f -> %.3f px, row error mean %.3f -> %.3f px, "
      "max %.3f -> %.3f px\n",
      r.all_pairs_rms_px, r.calibration.rms_px, r.all_pairs_mean_row_error_px,
      r.mean_rectified_row_error_px, r.all_pairs_max_row_error_px, r.max_rectified_row_error_px);
  EXPECT_GT(r.all_pairs_rms_px, 0.5);
  EXPECT_LT(r.calibration.rms_px, 0.25);
  EXPECT_LT(r.mean_rectified_row_error_px, 0.2);
}

TEST(RealCalibration, GivenOutlierRatioZeroWhenCalibratedThenEveryPairKept) {
  std::vector<PairCorners> pairs = sample_corners();
  pairs[2] = desynchronise(pairs[2], {0, 0.004, 0});
  BoardCalibrationParams params;
  params.outlier_ratio = 0.0;
  const auto result = calibrate_stereo(pairs, cv::Size(640, 480), params);
  ASSERT_TRUE(result.ok()) << result.error();
  EXPECT_TRUE(result->dropped.empty());
  EXPECT_EQ(result->pair_names.size(), pairs.size());
}

TEST(RealCalibration, GivenCalibrationWhenRealPairLutRectifiedThenBoardCornersShareRows) {
  // Given the calibration of the real sample pairs
  const auto result =
      calibrate_stereo(sample_corners(), cv::Size(640, 480), BoardCalibrationParams{});
  ASSERT_TRUE(result.ok()) << result.error();
  const Rectifier rect = Rectifier::create(result->calibration).value();
  // When a real pair goes through the fixed-point LUT and the board is found again
  cv::Mat l, r;
  ASSERT_TRUE(rect.rectify(cv::imread(name("left", 3), cv::IMREAD_GRAYSCALE),
                           cv::imread(name("right", 3), cv::IMREAD_GRAYSCALE), l, r)
                  .ok());
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
  EXPECT_TRUE(p.validate().ok());
  p.square_m = 0;
  EXPECT_EQ(p.validate().error().rfind("square_m", 0), 0u);
  p = {};
  p.min_pairs = 1;
  EXPECT_EQ(p.validate().error().rfind("min_pairs", 0), 0u);
  p = {};
  p.inner_corners = {1, 6};
  EXPECT_EQ(p.validate().error().rfind("inner_corners", 0), 0u);
  p = {};
  p.outlier_ratio = -1;
  EXPECT_EQ(p.validate().error().rfind("outlier_ratio", 0), 0u);
  p = {};
  p.outlier_min_px = std::nan("");
  EXPECT_EQ(p.validate().error().rfind("outlier_min_px", 0), 0u);
}

TEST(ParseBoardSize, ReadsColsByRowsAndRefusesTheRest) {
  EXPECT_EQ(parse_board_size("9x6"), cv::Size(9, 6));
  EXPECT_EQ(parse_board_size("8X6"), cv::Size(8, 6));
  EXPECT_FALSE(parse_board_size("9"));
  EXPECT_FALSE(parse_board_size("9x6x"));
  EXPECT_FALSE(parse_board_size("1x6"));
  EXPECT_FALSE(parse_board_size("9x51"));
  EXPECT_FALSE(parse_board_size("9*6"));
}

TEST(SingleCameraFitProblem, NamedOnlyWhenACameraAloneFitsBadly) {
  // Given calibrations whose single-camera fits are good, and one whose left camera is not
  BoardCalibrationResult good, bad;
  good.left_rms_px = 0.21;
  good.right_rms_px = 0.19;
  bad.left_rms_px = 2.72;
  bad.right_rms_px = 0.40;
  // Then only the bad one gets a note, naming both figures and the limit
  EXPECT_FALSE(single_camera_fit_problem(good).has_value());
  const auto note = single_camera_fit_problem(bad);
  ASSERT_TRUE(note.has_value());
  EXPECT_NE(note->find("2.72 px (left)"), std::string::npos) << *note;
  EXPECT_NE(note->find("0.40 px (right)"), std::string::npos) << *note;
  EXPECT_NE(note->find("above 1.00 px"), std::string::npos) << *note;
  // And a stricter limit catches the right camera too
  EXPECT_TRUE(single_camera_fit_problem(good, 0.2).has_value());
}

}  // namespace
}  // namespace stereoball::stereo
