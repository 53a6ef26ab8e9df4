// The real-stereo scorer on a hand-made truth file: verdicts, bands, the depth rule,
// exclusions, aggregates, and malformed files named by file and line.

#include "real_stereo_score.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace rs = stereoball::real_stereo;

namespace {

const char* kHeader =
    "pair,left,right,npts,rect_left_cx,rect_left_cy,rect_right_cx,rect_right_cy,rect_left_r,"
    "rect_right_r,avg_disparity,dy_mean,Z_m,implied_ball_diam_m,flag\n";

// Five pairs: a ball 70 px in radius at 1.66 m (dy 0.5), one 92 px at 1.2 m (dy -4), one with a
// moved ball (dy 14.5), one without a radius, one whose clicks are unusable.
std::string hand_made_truth() {
  return std::string(kHeader) +
         "1,left_01.jpg,right_01.jpg,2,1000.0,600.0,917.0,599.5,70.0,70.0,83.0,0.5,1.66,0.240,\n"
         "2,left_02.jpg,right_02.jpg,2,1246.0,887.5,1131.0,891.5,92.5,92.5,115.0,-4.0,1.2,0.229,"
         "diam_inconsistent\n"
         "3,left_03.jpg,right_03.jpg,2,993.0,580.0,910.0,565.5,70.5,71.5,83.0,14.5,1.66,0.242,"
         "dy>10px\n"
         "4,left_04.jpg,right_04.jpg,5,1275.9,573.1,1185.1,572.9,nan,nan,90.8,0.2,1.52,,"
         "not_2_edge_points;no_radius\n"
         "5,left_05.jpg,right_05.jpg,2,1241.5,851.0,1181.0,849.5,36.0,34.5,60.5,1.5,2.28,0.170,"
         "diam_inconsistent;clicks_not_on_ball_edges\n";
}

rs::Detection found_at(double x, double y, double z, double ms = 100) {
  rs::Detection d;
  d.found = true;
  d.status = "found";
  d.left_x_px = x;
  d.left_y_px = y;
  d.left_r_px = 70;
  d.z_m = z;
  d.processing_ms = ms;
  return d;
}

rs::Detection missed(const std::string& status, const std::string& reason, double ms = 100) {
  rs::Detection d;
  d.status = status;
  d.reason = reason;
  d.processing_ms = ms;
  return d;
}

std::vector<rs::TruthRow> truth() {
  auto rows = rs::parse_truth(hand_made_truth(), "truth.csv");
  EXPECT_TRUE(rows.ok()) << rows.error();
  return rows.ok() ? *rows : std::vector<rs::TruthRow>{};
}

std::string parse_error(const std::string& text) {
  auto rows = rs::parse_truth(text, "set/truth.csv");
  EXPECT_FALSE(rows.ok());
  return rows.ok() ? std::string() : rows.error();
}

}  // namespace

TEST(TruthFile, GivenTheHandMadeFileWhenParsedThenRowsFlagsAndExclusionsAreRead) {
  // Given / When the hand-made truth file
  const auto rows = truth();
  // Then every row is read with its columns by name, flags split at '|' and ';'
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_EQ(rows[0].pair, "1");
  EXPECT_EQ(rows[0].left, "left_01.jpg");
  EXPECT_DOUBLE_EQ(rows[0].left_cx, 1000.0);
  EXPECT_DOUBLE_EQ(rows[0].left_r, 70.0);
  EXPECT_DOUBLE_EQ(rows[0].z_m, 1.66);
  EXPECT_EQ(rows[0].line, 2u);
  EXPECT_TRUE(rows[0].depth_checked());
  EXPECT_FALSE(rows[1].depth_checked());  // diam_inconsistent
  EXPECT_EQ(rows[0].exclusion(), rs::Exclusion::kNone);
  EXPECT_EQ(rows[3].exclusion(), rs::Exclusion::kNoRadius);
  EXPECT_TRUE(std::isnan(rows[3].left_r));
  EXPECT_EQ(rows[4].exclusion(), rs::Exclusion::kUnusable);
  EXPECT_EQ(rows[4].flags.size(), 2u);
}

TEST(Scorer, GivenAFoundBallNearTheTruthAtItsDepthWhenScoredThenCorrect) {
  const auto rows = truth();
  // Given a detection 20 px off (allowed 0.35 * 70 = 24.5 px) at 1.70 m (+2.4 %)
  // When scored
  const auto s = rs::score_pair(rows[0], found_at(1012, 616, 1.70));
  // Then it is correct, with its errors reported
  EXPECT_EQ(s.verdict, rs::Verdict::kCorrect);
  EXPECT_NEAR(s.centre_error_px, 20.0, 1e-9);
  EXPECT_NEAR(s.depth_error, 0.04 / 1.66, 1e-9);
}

TEST(Scorer, GivenAFoundBallFarFromTheTruthWhenScoredThenWrong) {
  const auto rows = truth();
  // Given a detection 30 px off (allowed 24.5 px) at the right depth
  const auto s = rs::score_pair(rows[0], found_at(1030, 600, 1.66));
  // Then it is wrong, and why says the centre
  EXPECT_EQ(s.verdict, rs::Verdict::kWrong);
  EXPECT_NE(s.why.find("centre"), std::string::npos) << s.why;
}

TEST(Scorer, GivenASmallBallWhenScoredThenTheCentreAllowanceIsAtLeastSixPixels) {
  // Given a ball of radius 10 px (0.35 r = 3.5 px) and a detection 5.5 px off
  auto row = truth()[0];
  row.left_r = 10;
  // Then 6 px is allowed: correct; 6.5 px is not
  EXPECT_EQ(rs::score_pair(row, found_at(1005.5, 600, 1.66)).verdict, rs::Verdict::kCorrect);
  EXPECT_EQ(rs::score_pair(row, found_at(1006.5, 600, 1.66)).verdict, rs::Verdict::kWrong);
}

TEST(Scorer, GivenTheRightPlaceAtTheWrongDepthWhenScoredThenWrongOnlyWhereDepthIsConsistent) {
  const auto rows = truth();
  // Given a detection at the centre but 10 % too far
  // When the truth's depth is consistent: wrong, why names the depth
  const auto checked = rs::score_pair(rows[0], found_at(1000, 600, 1.66 * 1.10));
  EXPECT_EQ(checked.verdict, rs::Verdict::kWrong);
  EXPECT_NE(checked.why.find("depth"), std::string::npos) << checked.why;
  // When it is diam_inconsistent: the depth is not checked, correct
  const auto unchecked = rs::score_pair(rows[1], found_at(1246, 887.5, 1.2 * 1.5));
  EXPECT_EQ(unchecked.verdict, rs::Verdict::kCorrect);
  // And 4.9 % off passes where it is checked
  EXPECT_EQ(rs::score_pair(rows[0], found_at(1000, 600, 1.66 * 1.049)).verdict,
            rs::Verdict::kCorrect);
}

TEST(Scorer, GivenNoBallFoundWhenScoredThenMissedWithTheNodesStatusAndReason) {
  const auto rows = truth();
  const auto s = rs::score_pair(rows[0], missed("no_candidate", "no circle in the left eye"));
  EXPECT_EQ(s.verdict, rs::Verdict::kMissed);
  EXPECT_EQ(s.detection.reason, "no circle in the left eye");
}

TEST(Scorer, GivenExcludedRowsWhenScoredThenExcludedWhateverTheDetection) {
  const auto rows = truth();
  // Given a perfect-looking detection on a row without radius and one on an unusable row
  EXPECT_EQ(rs::score_pair(rows[3], found_at(1275.9, 573.1, 1.52)).verdict, rs::Verdict::kExcluded);
  EXPECT_EQ(rs::score_pair(rows[4], missed("no_candidate", "x")).verdict, rs::Verdict::kExcluded);
}

TEST(Scorer, GivenNaNOrHugeDetectionValuesWhenScoredThenNeverCorrect) {
  const auto rows = truth();
  EXPECT_EQ(rs::score_pair(rows[0], found_at(NAN, 600, 1.66)).verdict, rs::Verdict::kWrong);
  EXPECT_EQ(rs::score_pair(rows[0], found_at(1000, 600, NAN)).verdict, rs::Verdict::kWrong);
  EXPECT_EQ(rs::score_pair(rows[0], found_at(1e300, 1e300, 1.66)).verdict, rs::Verdict::kWrong);
  EXPECT_EQ(rs::score_pair(rows[0], found_at(1000, 600, INFINITY)).verdict, rs::Verdict::kWrong);
}

TEST(Summary, GivenScoresOfEveryKindWhenSummarizedThenBandsDenominatorReasonsAndTimes) {
  const auto rows = truth();
  // Given pair 1 correct (band <= 2), 2 missed (band 2-10), 3 wrong (band > 10), 4 and 5
  // excluded; detector times 10..50 ms
  std::vector<rs::PairScore> scores = {
      rs::score_pair(rows[0], found_at(1000, 600, 1.66, 10)),
      rs::score_pair(rows[1], missed("epipolar_mismatch", "row residual 12.5 px > 2.0 px", 20)),
      rs::score_pair(rows[2], found_at(300, 300, 5.0, 30)),
      rs::score_pair(rows[3], missed("no_candidate", "no circle in the left eye", 40)),
      rs::score_pair(rows[4], missed("no_candidate", "no circle in the right eye", 50)),
  };
  // When summarized
  const rs::Summary s = rs::summarize(scores);
  // Then the denominator is the pairs with a radius (3), excluded ones listed apart
  EXPECT_EQ(s.overall.total(), 3);
  EXPECT_EQ(s.overall.correct, 1);
  EXPECT_EQ(s.overall.wrong, 1);
  EXPECT_EQ(s.overall.missed, 1);
  ASSERT_EQ(s.excluded.size(), 2u);
  EXPECT_NE(s.excluded[0].find("4"), std::string::npos);
  // And each band holds its pair
  EXPECT_EQ(s.bands.at(rs::Band::kWithin2).correct, 1);
  EXPECT_EQ(s.bands.at(rs::Band::k2To10).missed, 1);
  EXPECT_EQ(s.bands.at(rs::Band::kOver10).wrong, 1);
  // And the miss is counted by its kind, numbers hidden
  ASSERT_EQ(s.miss_reasons.size(), 1u);
  EXPECT_EQ(s.miss_reasons.begin()->first, "epipolar_mismatch: row residual # px > # px");
  // And the times cover every frame: median 30, p90 50
  EXPECT_EQ(s.timed_frames, 5u);
  EXPECT_DOUBLE_EQ(s.median_ms, 30.0);
  EXPECT_DOUBLE_EQ(s.p90_ms, 50.0);
}

TEST(Reference, GivenAnotherMethodsFramesWhenSummarizedThenTimesRatiosAndHitsOfScoredPairs) {
  const auto rows = truth();
  // Given the pipeline's scores (CPU 30, 40, 50, 60, 70 ms) and a reference that ran on pairs
  // 1, 2, 3 and 4 (not 5): detect 5, 10, 15, 20 ms, decode 5 ms each; its circles hold pair 1's
  // ball (second circle), not pair 2's (40 px off; a 92.5 px ball allows 32.4), pair 3's (24 px
  // off; 70.5 px allows 24.7) and pair 4's (excluded: not counted)
  std::vector<rs::PairScore> scores;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    rs::Detection d = missed("no_candidate", "no circle in the left eye");
    d.cpu_ms = 30.0 + 10.0 * static_cast<double>(i);
    scores.push_back(rs::score_pair(rows[i], d));
  }
  std::vector<std::optional<rs::ReferenceFrame>> frames(rows.size());
  frames[0] = rs::ReferenceFrame{5, 5, {{10, 10, 8}, {1003, 604, 70}}};
  frames[1] = rs::ReferenceFrame{10, 5, {{1246 + 40, 887.5, 92}}};
  frames[2] = rs::ReferenceFrame{15, 5, {{993 + 24.0, 580, 70}}};
  frames[3] = rs::ReferenceFrame{20, 5, {{1275.9, 573.1, 60}}};
  // When summarized
  const rs::ReferenceSummary r = rs::summarize_reference(scores, frames);
  // Then the frames it ran on count, their medians and the per-frame ratio pipeline / (decode +
  // method): 30/10, 40/15, 50/20, 60/25 -> median of 3, 2.67, 2.5, 2.4
  EXPECT_EQ(r.frames, 4u);
  EXPECT_DOUBLE_EQ(r.median_detect_ms, 12.5);
  EXPECT_DOUBLE_EQ(r.median_decode_ms, 5.0);
  EXPECT_DOUBLE_EQ(r.median_frame_ms, 17.5);
  EXPECT_NEAR(r.median_pipeline_ratio, (40.0 / 15 + 50.0 / 20) / 2, 1e-12);
  // And the ball is among its circles in 2 of the 3 scored pairs it ran on
  EXPECT_EQ(r.scored, 3);
  EXPECT_EQ(r.ball_among_circles, 2);
}

TEST(Reference, GivenACentreJustOutsideTheAllowanceWhenMatchedThenNotTheBall) {
  const auto rows = truth();
  // Given pair 1's ball (r 70: allowance 24.5 px)
  // Then 24.5 px off matches, 24.6 px and NaN do not
  EXPECT_TRUE(rs::centre_matches(rows[0], 1000 + 24.5, 600));
  EXPECT_FALSE(rs::centre_matches(rows[0], 1000 + 24.6, 600));
  EXPECT_FALSE(rs::centre_matches(rows[0], std::nan(""), 600));
}

TEST(Bands, GivenRowOffsetsWhenBandedThenTheEdgesBelongBelow) {
  EXPECT_EQ(rs::band_of(2.0), rs::Band::kWithin2);
  EXPECT_EQ(rs::band_of(-2.0), rs::Band::kWithin2);
  EXPECT_EQ(rs::band_of(2.5), rs::Band::k2To10);
  EXPECT_EQ(rs::band_of(-10.0), rs::Band::k2To10);
  EXPECT_EQ(rs::band_of(10.5), rs::Band::kOver10);
}

TEST(Scaling, GivenHalfWidthWhenScaledThenCentresAndRadiiHalveButTheBandStays) {
  const auto row = truth()[2];
  const auto half = rs::scaled(row, 0.5);
  EXPECT_DOUBLE_EQ(half.left_cx, (row.left_cx + 0.5) * 0.5 - 0.5);
  EXPECT_DOUBLE_EQ(half.left_r, row.left_r * 0.5);
  EXPECT_DOUBLE_EQ(half.dy_px, row.dy_px);
  EXPECT_EQ(rs::score_pair(half, found_at(row.left_cx * 0.5, row.left_cy * 0.5, 1.66)).verdict,
            rs::Verdict::kCorrect);
}

TEST(TruthFile, GivenAMalformedLineWhenParsedThenTheErrorNamesFileAndLine) {
  // A letter in a number on line 3
  std::string text = std::string(kHeader) +
                     "1,l1.jpg,r1.jpg,2,1000,600,917,599.5,70,70,83,0.5,1.66,0.24,\n"
                     "2,l2.jpg,r2.jpg,2,12x4,600,917,599.5,70,70,83,0.5,1.66,0.24,\n";
  std::string e = parse_error(text);
  EXPECT_NE(e.find("set/truth.csv:3:"), std::string::npos) << e;
  EXPECT_NE(e.find("rect_left_cx"), std::string::npos) << e;
  // A missing field on line 2
  e = parse_error(std::string(kHeader) + "1,l1.jpg,r1.jpg,2,1000,600,917\n");
  EXPECT_NE(e.find("set/truth.csv:2:"), std::string::npos) << e;
  EXPECT_NE(e.find("fields"), std::string::npos) << e;
  // A header without Z_m
  e = parse_error("pair,left,right,rect_left_cx\n1,a,b,3\n");
  EXPECT_NE(e.find("set/truth.csv:1:"), std::string::npos) << e;
  EXPECT_NE(e.find("Z_m"), std::string::npos) << e;
  // The same pair twice (line 3)
  e = parse_error(std::string(kHeader) +
                  "1,l1.jpg,r1.jpg,2,1000,600,917,599.5,70,70,83,0.5,1.66,0.24,\n"
                  "1,l2.jpg,r2.jpg,2,1000,600,917,599.5,70,70,83,0.5,1.66,0.24,\n");
  EXPECT_NE(e.find("set/truth.csv:3:"), std::string::npos) << e;
  // An empty file
  e = parse_error("");
  EXPECT_NE(e.find("set/truth.csv"), std::string::npos) << e;
}

TEST(TruthFile, GivenNaNOrHugeValuesWhereNumbersMustBeWhenParsedThenRefusedWithTheLine) {
  // A NaN centre (only radii and Z_m may be nan)
  std::string e = parse_error(std::string(kHeader) +
                              "1,l1.jpg,r1.jpg,2,nan,600,917,599.5,70,70,83,0.5,1.66,0.24,\n");
  EXPECT_NE(e.find(":2:"), std::string::npos) << e;
  // A huge centre, an infinite depth, a negative radius, a path in the image column
  for (const char* bad : {"1,l1.jpg,r1.jpg,2,1e300,600,917,599.5,70,70,83,0.5,1.66,0.24,\n",
                          "1,l1.jpg,r1.jpg,2,1000,600,917,599.5,70,70,83,0.5,inf,0.24,\n",
                          "1,l1.jpg,r1.jpg,2,1000,600,917,599.5,-70,70,83,0.5,1.66,0.24,\n",
                          "1,../l1.jpg,r1.jpg,2,1000,600,917,599.5,70,70,83,0.5,1.66,0.24,\n"}) {
    e = parse_error(std::string(kHeader) + bad);
    EXPECT_NE(e.find("set/truth.csv:2:"), std::string::npos) << bad << " -> " << e;
  }
}
