// Each Pixel-to-Pixel rule on hand-built windows (paper figures 5, 6, 7, 8).

#include "ball_detector/core/p2p_rules.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <vector>

namespace stereoball::ball_detector {
namespace {

// The arc of figure 6a (k = 4): O at the origin, x right, y down.
std::vector<WindowPoint> figure6_arc() {
  return {{2, -1}, {3, -1}, {4, -1}, {0, 0}, {1, 0}, {-2, 1}, {-1, 1}, {-3, 2}, {-4, 3}};
}

std::vector<WindowPoint> mirrored(std::vector<WindowPoint> pts) {
  for (auto& p : pts) p.y = -p.y;
  return pts;
}

// A window image (2k+1 square plus margin) with the given points set around its centre.
BitImage window_image(const std::vector<WindowPoint>& pts, int k, int& cx, int& cy) {
  cv::Mat m(2 * k + 11, 2 * k + 11, CV_8U, cv::Scalar(0));
  cx = cy = k + 5;
  for (const auto& p : pts) m.at<uchar>(cy + p.y, cx + p.x) = 255;
  BitImage b;
  b.assign(m);
  return b;
}

TEST(WindowCount, GivenFigure6ArcWhenCountingThenItHoldsExactly2kPlus1) {
  int cx = 0, cy = 0;
  const BitImage img = window_image(figure6_arc(), 4, cx, cy);
  const int count = count_window_points(img, cx, cy, 4);
  EXPECT_EQ(count, 9);
  EXPECT_TRUE(window_count_ok(count, 4));
}

TEST(WindowCount, GivenCountsOtherThan2kPlus1ThenTheWindowIsRejected) {
  // Figure 8 a) an arc end (k + 1 points), b) an arc plus isolated points.
  EXPECT_FALSE(window_count_ok(6, 5));
  EXPECT_FALSE(window_count_ok(13, 5));
  EXPECT_FALSE(window_count_ok(1, 5));
  EXPECT_TRUE(window_count_ok(11, 5));
}

// Addition (arc isolation): given the figure 6 arc plus isolated points and a separate line in
// the window (figure 8b, count 13 != 9), when only the points 8-connected to O are kept, then
// exactly the arc's 9 points remain, in the same raster order as a plain collection of the arc.
TEST(ArcIsolation, GivenArcWithUnconnectedEdgesThenOnlyTheArcRemains) {
  std::vector<WindowPoint> pts = figure6_arc();
  const std::vector<WindowPoint> clutter = {{-4, -4}, {-3, -4}, {-2, -4}, {3, 3}};
  pts.insert(pts.end(), clutter.begin(), clutter.end());
  int cx = 0, cy = 0;
  const BitImage img = window_image(pts, 4, cx, cy);
  EXPECT_EQ(count_window_points(img, cx, cy, 4), 13);
  std::vector<std::uint64_t> rows(9);
  EXPECT_EQ(connected_window_rows(img, cx, cy, 4, rows), 9);
  std::vector<WindowPoint> got(9);
  ASSERT_EQ(collect_masked_points(rows, 4, got), 9);
  int ax = 0, ay = 0;
  const BitImage arc_only = window_image(figure6_arc(), 4, ax, ay);
  std::vector<WindowPoint> expected(9);
  ASSERT_EQ(collect_window_points(arc_only, ax, ay, 4, expected), 9);
  EXPECT_EQ(got, expected);
}

// Given a line touching the arc (a junction), then the component holds both and the count rule
// still rejects the window: only edges that merely share the window are ignored.
TEST(ArcIsolation, GivenLineJoiningTheArcThenTheComponentIsLargerThan2kPlus1) {
  std::vector<WindowPoint> pts = figure6_arc();
  for (int y = -4; y <= -1; ++y) pts.push_back({0, y});  // a vertical line ending at O
  int cx = 0, cy = 0;
  const BitImage img = window_image(pts, 4, cx, cy);
  std::vector<std::uint64_t> rows(9);
  EXPECT_EQ(connected_window_rows(img, cx, cy, 4, rows), 13);
  EXPECT_FALSE(window_count_ok(13, 4));
}

// Given a window with O alone (isolated point, figure 8), then the component is just O.
TEST(ArcIsolation, GivenIsolatedCentreThenComponentIsOnePoint) {
  int cx = 0, cy = 0;
  const BitImage img = window_image({{0, 0}, {3, 3}, {-4, 2}}, 4, cx, cy);
  std::vector<std::uint64_t> rows(9);
  EXPECT_EQ(connected_window_rows(img, cx, cy, 4, rows), 1);
}

TEST(WindowCount, GivenPointsOutsideTheWindowWhenCountingThenTheyAreIgnored) {
  auto pts = figure6_arc();
  pts.push_back({5, 0});  // just outside a k = 4 window
  pts.push_back({0, -5});
  int cx = 0, cy = 0;
  const BitImage img = window_image(pts, 4, cx, cy);
  EXPECT_EQ(count_window_points(img, cx, cy, 4), 9);
  EXPECT_EQ(count_window_points(img, cx, cy, 5), 11);
}

TEST(WindowCollect, GivenAWindowWhenCollectingThenPointsComeRelativeToOInRasterOrder) {
  int cx = 0, cy = 0;
  const BitImage img = window_image(figure6_arc(), 4, cx, cy);
  std::vector<WindowPoint> out(9);
  ASSERT_EQ(collect_window_points(img, cx, cy, 4, out), 9);
  EXPECT_EQ(out, figure6_arc());
}

TEST(ChordEnds, GivenFigure6ArcThenAIsFarthestAndBHasAnOppositeSign) {
  const auto pts = figure6_arc();
  const auto ends = find_chord_ends(pts);
  ASSERT_TRUE(ends.has_value());
  EXPECT_EQ(ends->a, (WindowPoint{-4, 3}));  // |x|+|y| = 7
  EXPECT_EQ(ends->b, (WindowPoint{4, -1}));  // farthest among x > 0 or y < 0
}

TEST(ChordEnds, GivenAnAngularPointAtORightAngleThenNoChordIsFound) {
  // Figure 5 point 1: both arms in one quadrant, no coordinate of opposite sign.
  std::vector<WindowPoint> corner{{0, 0}};
  for (int i = 1; i <= 5; ++i) {
    corner.push_back({i, 0});
    corner.push_back({0, i});
  }
  EXPECT_FALSE(find_chord_ends(corner).has_value());
  EXPECT_FALSE(analyse_window(corner, 5).has_value());
}

TEST(ChordEnds, GivenASharpAngleAtOThenNoChordIsFound) {
  std::vector<WindowPoint> corner{{0, 0}};
  for (int i = 1; i <= 5; ++i) {
    corner.push_back({i, i});
    corner.push_back({i / 2, i});
  }
  EXPECT_FALSE(find_chord_ends(corner).has_value());
}

TEST(ChordEnds, GivenL1DistanceThenItIsTheSumOfAbsoluteCoordinates) {
  EXPECT_EQ(l1_distance({-3, 4}), 7);
  EXPECT_EQ(l1_distance({0, 0}), 0);
  EXPECT_TRUE(opposite_sign({-1, 2}, {3, 2}));
  EXPECT_FALSE(opposite_sign({0, 2}, {3, 0}));  // zero has no sign
}

TEST(StraightSegment, GivenAxisAlignedAndDiagonalLinesThroughOThenEq3DetectsThem) {
  // Figure 7: A, B and O aligned.
  EXPECT_TRUE(is_straight_segment({-5, 0}, {5, 0}));
  EXPECT_TRUE(is_straight_segment({0, -5}, {0, 5}));
  EXPECT_TRUE(is_straight_segment({-5, -5}, {5, 5}));
  // A digital line of slope 1/2 through O: the intercepts stay within one pixel.
  EXPECT_TRUE(is_straight_segment({-5, -2}, {5, 3}));
}

TEST(StraightSegment, GivenArcEndsThenEq3DoesNotReject) {
  EXPECT_FALSE(is_straight_segment({-4, 3}, {4, -1}));
  EXPECT_FALSE(is_straight_segment({-5, 2}, {5, 2}));
}

TEST(StraightSegment, GivenAStraightSegmentWindowThenAnalysisRejectsIt) {
  std::vector<WindowPoint> line;
  for (int x = -5; x <= 5; ++x) line.push_back({x, 0});
  EXPECT_FALSE(analyse_window(line, 5).has_value());
}

TEST(Bisector, GivenChordEndsThenTheLinePassesThroughMidpointPerpendicularToAB) {
  const WindowPoint a{-4, 3}, b{4, -1};
  const VoteLine l = perpendicular_bisector(a, b);
  EXPECT_EQ(l.c2x, a.x + b.x);  // eq. (1), doubled
  EXPECT_EQ(l.c2y, a.y + b.y);
  EXPECT_EQ(l.nx * (b.x - a.x) + l.ny * (b.y - a.y), 0);
  EXPECT_NE(l.nx * l.nx + l.ny * l.ny, 0);
}

TEST(Concavity, GivenFigure6ArcThenTheLinePointsToTheConcaveSide) {
  const auto line = analyse_window(figure6_arc(), 4);
  ASSERT_TRUE(line.has_value());
  // O lies above the chord (smaller y), so the centre is below: positive y.
  EXPECT_GT(line->ny, 0);
  EXPECT_GT(line->nx * line->c2x + line->ny * line->c2y, 0);
}

TEST(Concavity, GivenTheMirroredArcThenTheDirectionFlips) {
  const auto up = analyse_window(figure6_arc(), 4);
  const auto down = analyse_window(mirrored(figure6_arc()), 4);
  ASSERT_TRUE(up && down);
  EXPECT_LT(down->ny, 0);
  EXPECT_EQ(up->nx, down->nx);
  EXPECT_EQ(up->ny, -down->ny);
}

TEST(Concavity, GivenALineWithCAtOThenThereIsNoConcavity) {
  EXPECT_FALSE(orient_to_concave_side(VoteLine{0, 0, 1, 0}).has_value());
}

TEST(Analysis, GivenADigitalCircleThenEveryAcceptedLinePointsAtTheCentre) {
  const int k = 5;
  cv::Mat m(120, 120, CV_8U, cv::Scalar(0));
  const cv::Point centre(60, 60);
  cv::circle(m, centre, 18, cv::Scalar(255), 1, cv::LINE_8);
  BitImage bits;
  bits.assign(m);
  int accepted = 0;
  std::vector<WindowPoint> buf(2 * k + 1);
  for (int y = k; y < m.rows - k; ++y)
    for (int x = k; x < m.cols - k; ++x) {
      if (!m.at<uchar>(y, x)) continue;
      if (!window_count_ok(count_window_points(bits, x, y, k), k)) continue;
      const int n = collect_window_points(bits, x, y, k, buf);
      const auto line = analyse_window(std::span<const WindowPoint>(buf.data(), n), k);
      if (!line) continue;
      ++accepted;
      const double to_cx = centre.x - x, to_cy = centre.y - y;
      const double cosang = (line->nx * to_cx + line->ny * to_cy) /
                            (std::hypot(line->nx, line->ny) * std::hypot(to_cx, to_cy));
      EXPECT_GT(cosang, std::cos(25.0 * CV_PI / 180.0)) << "at " << x << "," << y;
    }
  EXPECT_GT(accepted, 40);  // most of the ~100 circle pixels vote
}

TEST(BoxFilter, GivenAnImpulseThenItSpreadsEvenlyOverTheBox) {
  cv::Mat acc(21, 21, CV_16U, cv::Scalar(0));
  acc.at<std::uint16_t>(10, 10) = 25;
  const cv::Mat s = box_filter(acc, 5);
  ASSERT_EQ(s.type(), CV_32S);
  EXPECT_EQ(s.at<int>(10, 10), 25);  // all-ones mask: sums, as in the paper
  EXPECT_EQ(s.at<int>(12, 8), 25);
  EXPECT_EQ(s.at<int>(13, 10), 0);
}

TEST(BoxFilter, GivenScatteredVotesAroundAPointThenTheMaximumMovesToTheirIntersection) {
  // Lines that miss each other by a pixel: the raw maximum is elsewhere, the smoothed one not.
  cv::Mat acc(31, 31, CV_16U, cv::Scalar(0));
  acc.at<std::uint16_t>(3, 3) = 3;
  for (auto [x, y] : {std::pair{15, 14}, {16, 15}, {14, 15}, {15, 16}, {15, 15}})
    acc.at<std::uint16_t>(y, x) = 2;
  const cv::Point p = global_maximum(box_filter(acc, 3));
  EXPECT_EQ(p, cv::Point(15, 15));
}

TEST(GlobalMaximum, GivenAMapThenTheLargestCellIsReturned) {
  cv::Mat m(5, 7, CV_32S, cv::Scalar(0));
  m.at<int>(3, 6) = 2;
  m.at<int>(1, 1) = 1;
  EXPECT_EQ(global_maximum(m), cv::Point(6, 3));
}

}  // namespace
}  // namespace stereoball::ball_detector
