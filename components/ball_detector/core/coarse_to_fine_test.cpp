// The coarse-to-fine search functions: the level chosen from the width, the radius range split
// between the reduced image and the fine path, and a circle found on the reduced image refined
// at full resolution to within a stated tolerance of the full-resolution fit.

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <random>

#include "ball_detector/core/coarse_to_fine.hpp"
#include "ball_detector/core/p2p_detector.hpp"

namespace stereoball::ball_detector {
namespace {

// A bright disc on a darker, lightly noisy background (BGR).
cv::Mat disc_image(cv::Size size, cv::Point2d centre, double radius_px, unsigned seed) {
  cv::Mat img(size, CV_8UC3, cv::Scalar(60, 70, 80));
  cv::Mat noise(size, CV_8UC3);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::NORMAL, 0, 3);
  img += noise;
  // Drawn with a sub-pixel shift so the centre is not on the pixel grid.
  constexpr int kShift = 4;
  cv::circle(img,
             cv::Point(static_cast<int>(std::lround(centre.x * 16)),
                       static_cast<int>(std::lround(centre.y * 16))),
             static_cast<int>(std::lround(radius_px * 16)), cv::Scalar(40, 140, 220), cv::FILLED,
             cv::LINE_AA, kShift);
  return img;
}

// Full-resolution settings as the pipeline has them on a 2304-wide frame (k and radii scaled
// from the 640-px reference by 3.6).
PixelToPixelParams full_params() {
  PixelToPixelParams p;
  p.k_values = {11, 18};
  p.min_radius_px = 14.4;
  p.max_radius_px = 900.0;
  p.min_separation_px = 36.0;
  return p;
}

TEST(CoarseLevel, FollowsTheWidthAndTheBounds) {
  // Given the default settings: off
  CoarseToFineParams p;
  EXPECT_EQ(coarse_level(2304, p), 0);
  // And about 640 px wide on the reduced level
  p.target_width_px = 640;
  // Then a reference-sized image is not reduced, 1152 once, 2304 twice, 4608 at most max_level
  EXPECT_EQ(coarse_level(640, p), 0);
  EXPECT_EQ(coarse_level(1152, p), 1);
  EXPECT_EQ(coarse_level(2304, p), 2);
  p.max_level = 2;
  EXPECT_EQ(coarse_level(9216, p), 2);
  // And target 0 switches it off
  p.target_width_px = 0;
  EXPECT_EQ(coarse_level(2304, p), 0);
}

TEST(CoarseToFineParams, BadValuesAreNamed) {
  CoarseToFineParams p;
  EXPECT_TRUE(p.validate());
  p.min_coarse_radius_px = 0.0;
  const Status st = p.validate();
  ASSERT_FALSE(st);
  EXPECT_NE(st.error().find("min_coarse_radius_px"), std::string::npos);
  p = CoarseToFineParams{};
  p.max_level = 9;
  EXPECT_FALSE(p.validate());
}

TEST(SplitRadiusRange, SmallRadiiGoToTheFinePath) {
  // Given the radii 8-400 px at level 2 with 3.5 px the smallest coarse radius (14 px full)
  const RadiusSplit s = split_radius_range({8.0, 400.0}, 2, 3.5);
  // Then 14-400 px are searched on the reduced image (its pixels), 8-14 px at full resolution
  ASSERT_TRUE(holds_radii(s.coarse_px));
  EXPECT_DOUBLE_EQ(s.coarse_px.min_px, 3.5);
  EXPECT_DOUBLE_EQ(s.coarse_px.max_px, 100.0);
  ASSERT_TRUE(holds_radii(s.fine_px));
  EXPECT_DOUBLE_EQ(s.fine_px.min_px, 8.0);
  EXPECT_DOUBLE_EQ(s.fine_px.max_px, 14.0);
  // And a range above the limit has no fine part; level 0 is all fine
  EXPECT_FALSE(holds_radii(split_radius_range({14.4, 900.0}, 2, 3.5).fine_px));
  EXPECT_FALSE(holds_radii(split_radius_range({14.4, 900.0}, 0, 3.5).coarse_px));
}

TEST(ParamsAtLevel, KeepTheSceneWindowAndLoosenTheCoarseScore) {
  // Given the 2304-px settings
  const PixelToPixelParams full = full_params();
  // When reduced two levels
  const PixelToPixelParams p = params_at_level(full, 2);
  // Then k, radii and separation are a quarter (k rounded up), the score the coarse one
  EXPECT_EQ(p.k_values, (std::vector<int>{3, 5}));
  EXPECT_DOUBLE_EQ(p.min_radius_px, 3.6);
  EXPECT_DOUBLE_EQ(p.max_radius_px, 225.0);
  EXPECT_DOUBLE_EQ(p.min_separation_px, 9.0);
  EXPECT_LE(p.min_score, full.coarse_min_score);
  EXPECT_GE(p.max_circles, full.max_peaks_examined);
  EXPECT_TRUE(p.validate());
}

TEST(HoldsSeed, ARefinementThatMovedFarIsAnotherOutline) {
  // Given a seed of radius 40 px at (100, 100)
  const Circle seed{100.0, 100.0, 40.0, 0.6};
  // Then a refinement within 0.15 radii in centre and radius holds it
  EXPECT_TRUE(holds_seed({104.0, 103.0, 44.0, 0.8}, seed, 0.15));
  // And one whose centre moved 8 px (0.2 radii), or whose radius grew by 8 px, does not
  EXPECT_FALSE(holds_seed({108.0, 100.0, 40.0, 0.8}, seed, 0.15));
  EXPECT_FALSE(holds_seed({100.0, 100.0, 48.0, 0.8}, seed, 0.15));
  // And 0 switches the check off
  EXPECT_TRUE(holds_seed({300.0, 100.0, 10.0, 0.8}, seed, 0.0));
}

TEST(ToFullResolution, BlockCentresMapBack) {
  // Given a circle at reduced pixel (10, 20), radius 5, level 2 (blocks of 4)
  const Circle c = to_full_resolution({10.0, 20.0, 5.0, 0.7}, 2);
  // Then its centre is the block's centre and the radius four times larger
  EXPECT_DOUBLE_EQ(c.x_px, 41.5);
  EXPECT_DOUBLE_EQ(c.y_px, 81.5);
  EXPECT_DOUBLE_EQ(c.radius_px, 20.0);
  EXPECT_DOUBLE_EQ(c.score, 0.7);
}

TEST(RefineCoarseCircles, CoarseCircleRefinedToTheFullResolutionFit) {
  // Given a 1152x648 frame with a ball of radius 37.3 px at (611.4, 287.7)
  const cv::Point2d centre(611.4, 287.7);
  const double radius = 37.3;
  const cv::Mat img = disc_image({1152, 648}, centre, radius, 7);
  PixelToPixelParams full = full_params();
  full.k_values = {5, 9};
  full.min_radius_px = 7.2;
  full.max_radius_px = 216.0;
  full.min_separation_px = 18.0;
  // When the image reduced one level is searched and its circles refined at full resolution
  CoarseToFineParams c2f;
  c2f.target_width_px = 640;
  const int level = coarse_level(img.cols, c2f);
  ASSERT_EQ(level, 1);
  cv::Mat reduced;
  reduce_image(img, level, reduced);
  EXPECT_EQ(reduced.size(), cv::Size(576, 324));
  PixelToPixelDetector coarse(params_at_level(full, level));
  const std::vector<Circle> found_coarse = coarse.detect(reduced);
  ASSERT_FALSE(found_coarse.empty());
  PixelToPixelDetector fine(full);
  ASSERT_TRUE(fine.find_edges(img));  // the full-resolution edges only, no votes
  const std::vector<Circle> found =
      refine_coarse_circles(fine, found_coarse, level, c2f.max_refine_shift);
  // And the whole frame is searched at full resolution for comparison
  PixelToPixelDetector reference(full);
  const std::vector<Circle> whole = reference.detect(img);
  // Then the refined circle is within 0.5 px of the full-resolution fit, and within 1 px of the
  // drawn disc (the edge step's own bias, which the full-resolution fit shares)
  ASSERT_FALSE(found.empty());
  ASSERT_FALSE(whole.empty());
  const Circle& a = found.front();
  const Circle& b = whole.front();
  EXPECT_LT(std::hypot(a.x_px - b.x_px, a.y_px - b.y_px), 0.5);
  EXPECT_LT(std::abs(a.radius_px - b.radius_px), 0.5);
  EXPECT_LT(std::hypot(a.x_px - centre.x, a.y_px - centre.y), 1.0);
  EXPECT_LT(std::abs(a.radius_px - radius), 1.0);
  EXPECT_GE(a.score, full.min_score);
}

TEST(RefineCoarseCircles, BallBelowTheCoarseLimitIsFoundByTheFinePath) {
  // Given a 2304x1296 frame with a small ball (radius 11 px: under 3 px on level 2)
  const cv::Point2d centre(1500.3, 700.6);
  const double radius = 11.0;
  const cv::Mat img = disc_image({2304, 1296}, centre, radius, 11);
  PixelToPixelParams full = full_params();
  full.min_radius_px = 8.0;
  CoarseToFineParams c2f;
  c2f.target_width_px = 640;
  const int level = coarse_level(img.cols, c2f);
  ASSERT_EQ(level, 2);
  const RadiusSplit split =
      split_radius_range({full.min_radius_px, full.max_radius_px}, level, c2f.min_coarse_radius_px);
  // When the reduced image is searched over its part of the range
  cv::Mat reduced;
  reduce_image(img, level, reduced);
  ASSERT_TRUE(holds_radii(split.coarse_px));
  PixelToPixelParams coarse_params = params_at_level(full, level);
  coarse_params.min_radius_px = split.coarse_px.min_px;
  PixelToPixelDetector coarse(coarse_params);
  PixelToPixelDetector fine(full);
  ASSERT_TRUE(fine.find_edges(img));
  const EdgeThresholds thresholds = thresholds_of(fine.edge_map());
  const auto refined = refine_coarse_circles(fine, coarse.detect(reduced), level);
  // Then nothing of the ball's size comes from it (the ball is below the coarse limit) ...
  for (const Circle& c : refined) EXPECT_GE(c.radius_px, split.fine_px.max_px - 1.0);
  // ... and the fine path (full resolution, the small radii only) finds it within 1 px
  ASSERT_TRUE(holds_radii(split.fine_px));
  const auto small = fine.detect(img, thresholds, SearchHints{split.fine_px});
  ASSERT_FALSE(small.empty());
  EXPECT_LT(std::hypot(small.front().x_px - centre.x, small.front().y_px - centre.y), 1.0);
  EXPECT_LT(std::abs(small.front().radius_px - radius), 1.0);
}

}  // namespace
}  // namespace stereoball::ball_detector
