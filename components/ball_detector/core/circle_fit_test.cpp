// Additions: least-squares circle fit, angular coverage score.

#include "ball_detector/core/circle_fit.hpp"
#include "ball_detector/core/synthetic.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace stereoball::ball_detector {
namespace {

std::vector<cv::Point2d> arc(double cx, double cy, double r, double a0, double a1, int n) {
  std::vector<cv::Point2d> pts;
  for (int i = 0; i < n; ++i) {
    const double a = a0 + (a1 - a0) * i / (n - 1);
    pts.emplace_back(cx + r * std::cos(a), cy + r * std::sin(a));
  }
  return pts;
}

TEST(FitCircle, GivenExactPointsThenTheCircleIsRecovered) {
  const auto c = fit_circle(arc(12.3, -4.7, 9.5, 0.0, 2 * std::numbers::pi, 40));
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->x_px, 12.3, 1e-6);
  EXPECT_NEAR(c->y_px, -4.7, 1e-6);
  EXPECT_NEAR(c->radius_px, 9.5, 1e-6);
}

TEST(FitCircle, GivenRoundedPointsOnAQuarterArcThenTheCentreIsWithinAPixel) {
  auto pts = arc(50.4, 40.6, 30.0, 0.2, 1.8, 60);
  for (auto& p : pts) p = cv::Point2d(std::round(p.x), std::round(p.y));
  const auto c = fit_circle(pts);
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->x_px, 50.4, 1.0);
  EXPECT_NEAR(c->y_px, 40.6, 1.0);
}

TEST(FitCircle, GivenTooFewOrCollinearPointsThenNoCircle) {
  EXPECT_FALSE(fit_circle(std::vector<cv::Point2d>{{0, 0}, {1, 1}}).has_value());
  EXPECT_FALSE(fit_circle(std::vector<cv::Point2d>{{0, 0}, {1, 1}, {2, 2}, {3, 3}}).has_value());
}

TEST(FitCircle, GivenAnInnerArcBesideTheOutlineThenTheRobustFitKeepsToTheOutline) {
  // A patterned ball near its rim: a texture arc 2.5 px inside the outline over a quarter of it.
  auto pts = arc(60.0, 50.0, 40.0, 0.0, 2 * std::numbers::pi, 240);
  const auto inner = arc(60.0, 50.0, 37.5, -2.2, -0.7, 60);
  pts.insert(pts.end(), inner.begin(), inner.end());
  const auto plain = fit_circle(pts);
  const auto robust = fit_circle(pts, 0.6);
  ASSERT_TRUE(plain.has_value());
  ASSERT_TRUE(robust.has_value());
  EXPECT_GT(std::hypot(plain->y_px - 50.0, plain->radius_px - 40.0), 0.3);
  EXPECT_NEAR(robust->x_px, 60.0, 0.05);
  EXPECT_NEAR(robust->y_px, 50.0, 0.05);
  EXPECT_NEAR(robust->radius_px, 40.0, 0.05);
}

TEST(FitCircle, GivenAHeldRadiusThenOnlyTheCentreMovesAndAnInnerArcNoLongerShrinksTheCircle) {
  // A small patterned ball: its rim over 240 degrees, and over the rest a stripe boundary
  // 1.4 px inside the rim instead of the rim itself
  auto pts = arc(30.0, 20.0, 9.0, -2.0 * std::numbers::pi / 3.0, 2.0 * std::numbers::pi / 3.0, 48);
  const auto inner = arc(30.0, 20.0, 7.6, 2.2, 4.1, 24);
  pts.insert(pts.end(), inner.begin(), inner.end());
  // Free, the circle shrinks onto the boundary on that side and its centre moves away from it
  const auto free_fit = fit_circle(pts, 0.6);
  ASSERT_TRUE(free_fit.has_value());
  EXPECT_GT(std::abs(free_fit->x_px - 30.0), 0.3);
  EXPECT_LT(free_fit->radius_px, 8.8);
  // Held at the rim's radius, the circle keeps to the rim
  const auto held = fit_circle(pts, 0.6, 9.0);
  ASSERT_TRUE(held.has_value());
  EXPECT_EQ(held->radius_px, 9.0);
  EXPECT_NEAR(held->x_px, 30.0, 0.1);
  EXPECT_NEAR(held->y_px, 20.0, 0.1);
}

TEST(RefineCircle, GivenHoldRadiusThenTheSeedsRadiusIsKeptAndTheCentreRefined) {
  const cv::Mat img = spotted_disc_image({120, 120}, {60, 60}, 20, 0, 0);
  EdgeMap e;
  compute_edge_map(img, EdgeParams{}, e);
  // The radius the edges give (a stereo partner's fit has the same edge-position bias)
  const auto free_fit = refine_circle(e, Circle{60.0, 60.0, 20.0, 0.0}, RefineParams{});
  ASSERT_TRUE(free_fit.has_value());
  RefineParams held;
  held.hold_radius = true;
  const auto c = refine_circle(e, Circle{61.0, 60.6, free_fit->radius_px, 0.0}, held);
  ASSERT_TRUE(c.has_value());
  EXPECT_DOUBLE_EQ(c->radius_px, free_fit->radius_px);
  EXPECT_NEAR(c->x_px, 60.0, 0.15);
  EXPECT_NEAR(c->y_px, 60.0, 0.15);
  EXPECT_GE(c->score, free_fit->score - 0.05) << "free fit " << free_fit->score;
}

TEST(RefineCircle, GivenAPanelTouchingTheRimOfAColourDiscThenTheRobustFitFindsTheRim) {
  // An orange disc with white spots just inside its rim on grey, as colour edges see a
  // panelled ball: each spot's boundary runs beside the outline a pixel or two inside it.
  const cv::Mat img = spotted_disc_image({200, 200}, {100, 100}, 40, 18, 20);
  EdgeMap e;
  compute_edge_map(img, EdgeParams{}, e);
  const Circle seed{100.5, 101.5, 38.5, 0};
  RefineParams least_squares;
  least_squares.robust_fit_floor_px = 0.0;
  const auto pulled = refine_circle(e, seed, least_squares);
  RefineParams robust;
  robust.robust_fit_floor_px = 0.6;
  const auto c = refine_circle(e, seed, robust);
  ASSERT_TRUE(pulled.has_value());
  ASSERT_TRUE(c.has_value());
  // Unweighted, the spots' boundaries pull the centre a pixel towards them.
  EXPECT_GT(std::hypot(pulled->x_px - 100.0, pulled->y_px - 100.0), 0.5);
  EXPECT_NEAR(c->x_px, 100.0, 0.15);
  EXPECT_NEAR(c->y_px, 100.0, 0.15);
  EXPECT_NEAR(c->radius_px, 40.0, 1.0);  // the same edge-position bias as a plain disc
}

TEST(AngularCoverage, GivenFullAndHalfCirclesThenCoverageIsOneAndAHalf) {
  const Circle c{0, 0, 20, 0};
  EXPECT_NEAR(angular_coverage(c, arc(0, 0, 20, 0, 2 * std::numbers::pi, 400)), 1.0, 0.02);
  EXPECT_NEAR(angular_coverage(c, arc(0, 0, 20, 0, std::numbers::pi, 400)), 0.5, 0.05);
  EXPECT_EQ(angular_coverage(c, std::vector<cv::Point2d>{}), 0.0);
}

// The sector of a point as angular_coverage defines it (atan2), for the test below.
int atan2_sector(const Circle& c, const cv::Point2d& p, int sectors) {
  const double a = std::atan2(p.y - c.y_px, p.x - c.x_px) + std::numbers::pi;
  return std::min(sectors - 1, static_cast<int>(a / (2.0 * std::numbers::pi) * sectors));
}

TEST(AngularCoverage, GivenPointsOnAndBetweenSectorBoundariesThenEachLandsInItsAtan2Sector) {
  // Given circles of 8 to 180 sectors and points at random angles, on the sector boundaries
  // (as near as doubles get), on the axes and at the centre
  cv::RNG rng(38);
  int pairs = 0;
  for (const double r : {3.0, 7.3, 20.0, 41.5, 86.0, 200.0}) {
    const Circle c{101.25, -37.5, r, 0.0};
    const int sectors = std::clamp(static_cast<int>(2.0 * std::numbers::pi * r / 3.0), 8, 180);
    std::vector<cv::Point2d> pts;
    for (int i = 0; i < 400; ++i) {
      const double a = rng.uniform(-std::numbers::pi, std::numbers::pi);
      const double d = rng.uniform(0.5, 2.0) * r;
      pts.emplace_back(c.x_px + d * std::cos(a), c.y_px + d * std::sin(a));
    }
    for (int s = 0; s <= sectors; ++s) {
      const double a = s * 2.0 * std::numbers::pi / sectors - std::numbers::pi;
      for (const double eps : {-1e-12, 0.0, 1e-12})
        pts.emplace_back(c.x_px + r * std::cos(a + eps), c.y_px + r * std::sin(a + eps));
    }
    for (const cv::Point2d d : {cv::Point2d(1, 0), cv::Point2d(-1, 0), cv::Point2d(0, 1),
                                cv::Point2d(0, -1), cv::Point2d(-1, -0.0), cv::Point2d(0, 0)})
      pts.push_back(cv::Point2d(c.x_px, c.y_px) + r * d);
    // When each is paired with the next, then the coverage counts one sector for two points in
    // one sector and two otherwise, as the atan2 sectors say
    for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
      const std::vector<cv::Point2d> two{pts[i], pts[i + 1]};
      const int expected =
          atan2_sector(c, pts[i], sectors) == atan2_sector(c, pts[i + 1], sectors) ? 1 : 2;
      ASSERT_EQ(angular_coverage(c, two), static_cast<double>(expected) / sectors)
          << "r " << r << " points " << pts[i] << " " << pts[i + 1];
      ++pairs;
    }
  }
  EXPECT_GT(pairs, 3000);
}

TEST(RefineCircle, GivenARoughSeedOnADiscThenRefinementIsSubPixelAndScoresHigh) {
  cv::Mat img(200, 200, CV_8UC3, cv::Scalar(60, 60, 60));
  // Sub-pixel centre (shift = 4 bits): (100.25, 95.75), radius 40.
  cv::circle(img, {100 * 16 + 4, 95 * 16 + 12}, 40 * 16, cv::Scalar(200, 200, 200), cv::FILLED,
             cv::LINE_AA, 4);
  EdgeMap e;
  compute_edge_map(img, EdgeParams{}, e);
  const auto c = refine_circle(e, Circle{102, 94, 37, 0}, RefineParams{});
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->x_px, 100.25, 0.3);
  EXPECT_NEAR(c->y_px, 95.75, 0.3);
  EXPECT_NEAR(c->radius_px, 40.0, 1.0);
  EXPECT_GT(c->score, 0.9);
}

TEST(RefineCircle, GivenGiveUpBelowThenOnlyCandidatesThatCannotReachItAreDropped) {
  // Given a full disc and a disc whose outline shows over a third of its circumference only
  // (the rest hidden in a same-coloured region)
  cv::Mat img(200, 400, CV_8UC3, cv::Scalar(60, 60, 60));
  cv::circle(img, {100, 100}, 40, cv::Scalar(200, 200, 200), cv::FILLED, cv::LINE_AA);
  cv::circle(img, {300, 100}, 40, cv::Scalar(200, 200, 200), cv::FILLED, cv::LINE_AA);
  cv::rectangle(img, cv::Rect(240, 40, 80, 120), cv::Scalar(200, 200, 200), cv::FILLED);
  EdgeMap e;
  compute_edge_map(img, EdgeParams{}, e);
  RefineParams plain, giving_up;
  giving_up.give_up_below = 0.5;
  giving_up.clutter_ring_per_radius = plain.clutter_ring_per_radius = 0.1;
  // When both refine the same seeds
  const auto full_plain = refine_circle(e, Circle{101, 99, 38, 0}, plain);
  const auto full_giving_up = refine_circle(e, Circle{101, 99, 38, 0}, giving_up);
  const auto part_plain = refine_circle(e, Circle{301, 99, 38, 0}, plain);
  const auto part_giving_up = refine_circle(e, Circle{301, 99, 38, 0}, giving_up);
  // Then the full disc is refined to the same circle and score, and the partial one, which
  // scores below the threshold when refined fully, is given up
  ASSERT_TRUE(full_plain && full_giving_up);
  EXPECT_EQ(full_plain->x_px, full_giving_up->x_px);
  EXPECT_EQ(full_plain->radius_px, full_giving_up->radius_px);
  EXPECT_EQ(full_plain->score, full_giving_up->score);
  EXPECT_GT(full_giving_up->score, 0.9);
  ASSERT_TRUE(part_plain.has_value());
  EXPECT_LT(part_plain->score, 0.5);
  EXPECT_FALSE(part_giving_up.has_value());
}

TEST(ScoreCircle, GivenTheRightCircleThenScoreIsHighAndForAWrongOneLow) {
  cv::Mat img(200, 200, CV_8U, cv::Scalar(60));
  cv::circle(img, {100, 100}, 40, cv::Scalar(200), cv::FILLED, cv::LINE_AA);
  EdgeMap e;
  compute_edge_map(img, EdgeParams{}, e);
  const auto right = refine_circle(e, Circle{100, 100, 40, 0}, RefineParams{});
  ASSERT_TRUE(right.has_value());
  EXPECT_GT(score_circle(e, *right, RefineParams{}), 0.9);
  EXPECT_LT(score_circle(e, Circle{130, 100, 20, 0}, RefineParams{}), 0.3);
  EXPECT_LT(score_circle(e, Circle{100, 100, 35, 0}, RefineParams{}), 0.1);
}

}  // namespace
}  // namespace stereoball::ball_detector

namespace stereoball::ball_detector {
namespace {

// Given a circle half outside the frame with its visible half fully supported, then the
// in-frame coverage is 1 (the plain coverage 0.5); with less than half inside, 0.
TEST(CoverageInFrame, GivenCircleCutByTheBorderThenVisiblePartDecides) {
  const Circle c{0.0, 50.0, 20.0, 0.0};  // centre on the left border of a 100x100 frame
  const cv::Rect2d frame(0, 0, 100, 100);
  const auto right_half = arc(0, 50, 20, -std::numbers::pi / 2, std::numbers::pi / 2, 400);
  EXPECT_NEAR(angular_coverage(c, right_half), 0.5, 0.05);
  EXPECT_NEAR(angular_coverage_in_frame(c, right_half, frame, 0.4), 1.0, 0.05);
  const Circle mostly_out{-10.0, 50.0, 20.0, 0.0};
  EXPECT_EQ(angular_coverage_in_frame(mostly_out, right_half, frame, 0.5), 0.0);
}

TEST(ClutterRings, GivenDenseTextureThenACircleThroughItScoresLowOnlyWithTheRings) {
  cv::Mat texture(200, 200, CV_8UC1);
  cv::RNG rng(3);
  rng.fill(texture, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(texture, texture, cv::Size(0, 0), 0.8);
  cv::Mat ball(200, 200, CV_8UC1, cv::Scalar(60));
  cv::circle(ball, {100, 100}, 40, cv::Scalar(180), cv::FILLED, cv::LINE_AA);
  EdgeParams ep;
  ep.max_high_threshold = 60.0;  // keep the texture's edges
  EdgeMap noise_edges, ball_edges;
  compute_edge_map(texture, ep, noise_edges);
  compute_edge_map(ball, EdgeParams{}, ball_edges);
  const Circle c{100.0, 100.0, 40.0, 0.0};
  RefineParams plain, rings;
  rings.clutter_ring_per_radius = 0.1;
  const double texture_plain = score_circle(noise_edges, c, plain);
  EXPECT_GT(texture_plain, 0.3) << "texture covers many of the circle's sectors";
  EXPECT_LT(score_circle(noise_edges, c, rings), 0.5 * texture_plain);
  EXPECT_GT(score_circle(ball_edges, c, rings), 0.9);  // a clean outline keeps its score
}

// A 300x300 floor of dense dark texture (grey levels 0-120, blurred a little).
cv::Mat dark_textured_floor() {
  cv::Mat floor(300, 300, CV_8UC1);
  cv::RNG rng(5);
  rng.fill(floor, cv::RNG::UNIFORM, 0, 120);
  cv::GaussianBlur(floor, floor, cv::Size(0, 0), 0.8);
  return floor;
}

// Edges of image with a low Canny ceiling, so that texture keeps its edges beside an outline's.
EdgeMap texture_keeping_edges(const cv::Mat& image) {
  EdgeParams ep;
  ep.max_high_threshold = 30.0;
  EdgeMap edges;
  compute_edge_map(image, ep, edges);
  return edges;
}

TEST(ClutterRings, GivenAPlainBallOnATexturedFloorThenItKeepsItsScoreAndOnlyLargeCirclesAreJudged) {
  // Given a bright plain disc on dense dark texture: the ring outside it lies on texture, the ring
  // inside on the plain ball
  cv::Mat floor = dark_textured_floor();
  cv::circle(floor, {80, 80}, 40, cv::Scalar(230), cv::FILLED, cv::LINE_AA);
  const EdgeMap edges = texture_keeping_edges(floor);
  const Circle ball{80.0, 80.0, 40.5, 0.0};
  RefineParams plain, rings;
  rings.clutter_ring_per_radius = 0.1;
  // When scored with the rings, Then the cleaner (inner) ring takes almost nothing off
  const double without = score_circle(edges, ball, plain);
  ASSERT_GT(without, 0.8);
  EXPECT_GT(score_circle(edges, ball, rings), without - 0.15);
  // And a large chance circle in the texture loses most of its score, only while it is at
  // least clutter_min_radius_px large
  const Circle chance{200.0, 200.0, 70.0, 0.0};
  const double chance_plain = score_circle(edges, chance, plain);
  ASSERT_GT(chance_plain, 0.3);
  EXPECT_LT(score_circle(edges, chance, rings), 0.5 * chance_plain);
  rings.clutter_min_radius_px = 71.0;
  EXPECT_DOUBLE_EQ(score_circle(edges, chance, rings), chance_plain);
}

TEST(ClutterRings, GivenRadiiBetweenOnceAndTwiceTheMinRadiusThenTheRingsWeighInGradually) {
  // Given the chance circle of radius 70 in dense texture and its score with the rings at
  // full weight
  const EdgeMap edges = texture_keeping_edges(dark_textured_floor());
  const Circle chance{150.0, 150.0, 70.0, 0.0};
  RefineParams rings;
  rings.clutter_ring_per_radius = 0.1;
  const double plain = score_circle(edges, chance, RefineParams{});
  const double full = score_circle(edges, chance, rings);
  ASSERT_LT(full, plain - 0.1);
  // When the radius is twice the min radius or more, Then the rings count fully
  rings.clutter_min_radius_px = 35.0;
  EXPECT_DOUBLE_EQ(score_circle(edges, chance, rings), full);
  // When it is 1.5 times the min radius, Then they take half of what they take at full weight
  rings.clutter_min_radius_px = 70.0 / 1.5;
  EXPECT_NEAR(score_circle(edges, chance, rings), plain - 0.5 * (plain - full), 1e-9);
  // When it is 1.25 times, a quarter
  rings.clutter_min_radius_px = 70.0 / 1.25;
  EXPECT_NEAR(score_circle(edges, chance, rings), plain - 0.25 * (plain - full), 1e-9);
}

}  // namespace
}  // namespace stereoball::ball_detector
