// Colour-region seeds on hand-built images: a two-tone ball whose light half is the floor's
// grey, grey and badly shaped regions, a colourful floor, a ball of a colour brown planks lack,
// and bad input.

#include "ball_detector/core/colour_seeds.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>

#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/core/synthetic.hpp"

namespace stereoball::ball_detector {
namespace {

const cv::Scalar kFloor(170, 170, 170);
const cv::Scalar kPurple(150, 40, 120);  // BGR
const cv::Scalar kWhite(178, 178, 178);  // the light stripes: nearly the floor's grey
const Circle kSeededBall{150.0, 130.0, 24.0, 0.0};

// A light-grey tiled floor (darker joints every 24 px) with sensor noise.
cv::Mat tiled_floor(cv::Size size, int seed) {
  cv::Mat img(size, CV_8UC3, kFloor);
  for (int x = 12; x < size.width; x += 24)
    cv::line(img, {x, 0}, {x, size.height}, {120, 120, 120});
  for (int y = 12; y < size.height; y += 24)
    cv::line(img, {0, y}, {size.width, y}, {120, 120, 120});
  return with_sensor_noise(img, seed);
}

// Purple and near-floor-white diagonal stripes, 6 px wide, filling circle c.
void draw_striped_ball(cv::Mat& img, const Circle& c) {
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) {
      const double dx = x - c.x_px, dy = y - c.y_px;
      if (dx * dx + dy * dy > c.radius_px * c.radius_px) continue;
      const bool purple = static_cast<int>(std::floor((dx + dy + 1000.0) / 6.0)) % 2 == 0;
      const cv::Scalar& s = purple ? kPurple : kWhite;
      img.at<cv::Vec3b>(y, x) =
          cv::Vec3b(static_cast<std::uint8_t>(s[0]), static_cast<std::uint8_t>(s[1]),
                    static_cast<std::uint8_t>(s[2]));
    }
}

TEST(ColourSeeds, GivenStripedBallWhoseLightStripesMatchTheFloor_ThenOneSeedAtTheBall) {
  cv::Mat img = tiled_floor({320, 240}, 1);
  draw_striped_ball(img, kSeededBall);
  const auto seeds = colour_blob_seeds(img, 4.0, 120.0);
  ASSERT_EQ(seeds.size(), 1u);
  EXPECT_LT(std::hypot(seeds[0].x_px - kSeededBall.x_px, seeds[0].y_px - kSeededBall.y_px), 4.0);
  EXPECT_NEAR(seeds[0].radius_px, kSeededBall.radius_px, 6.0);
}

TEST(ColourSeeds, GivenTheSeedRefinedOnTheEdges_ThenTheBallsOutlineWithinAPixel) {
  cv::Mat img = tiled_floor({320, 240}, 2);
  draw_striped_ball(img, kSeededBall);
  PixelToPixelDetector det{PixelToPixelParams{}};
  ASSERT_TRUE(det.cast_votes(img));
  const auto found = det.refine_seeds(colour_blob_seeds(img, 4.0, 120.0));
  ASSERT_FALSE(found.empty());
  EXPECT_LT(std::hypot(found[0].x_px - kSeededBall.x_px, found[0].y_px - kSeededBall.y_px), 1.0);
  EXPECT_NEAR(found[0].radius_px, kSeededBall.radius_px, 1.0);
}

TEST(ColourSeeds, GivenGreyBallOrRegionsOfTheWrongSizeOrShape_ThenNoSeed) {
  // A grey ball: no chroma to stand out
  cv::Mat grey = tiled_floor({320, 240}, 3);
  cv::circle(grey, {150, 130}, 24, {90, 90, 90}, cv::FILLED);
  EXPECT_TRUE(colour_blob_seeds(grey, 4.0, 120.0).empty());
  // The striped ball outside the radius range asked for
  cv::Mat ball = tiled_floor({320, 240}, 4);
  draw_striped_ball(ball, kSeededBall);
  EXPECT_TRUE(colour_blob_seeds(ball, 40.0, 120.0).empty());
  EXPECT_TRUE(colour_blob_seeds(ball, 4.0, 12.0).empty());
  // A purple bar (aspect 8) and a thin purple ring (little of its box filled)
  cv::Mat shapes = tiled_floor({320, 240}, 5);
  cv::rectangle(shapes, cv::Rect(20, 20, 80, 10), kPurple, cv::FILLED);
  cv::circle(shapes, {220, 150}, 40, kPurple, 1);
  EXPECT_TRUE(colour_blob_seeds(shapes, 4.0, 120.0).empty());
}

TEST(ColourSeeds, GivenManyColouredRegions_ThenAtMostMaxSeedsLargestFirst) {
  cv::Mat img = tiled_floor({320, 240}, 6);
  for (int i = 0; i < 6; ++i) cv::circle(img, {30 + 50 * i, 60}, 6 + 2 * i, kPurple, cv::FILLED);
  ColourSeedParams p;
  p.max_seeds = 3;
  const auto seeds = colour_blob_seeds(img, 4.0, 120.0, p);
  ASSERT_EQ(seeds.size(), 3u);
  EXPECT_GT(seeds[0].radius_px, seeds[1].radius_px);
  EXPECT_GT(seeds[1].radius_px, seeds[2].radius_px);
  EXPECT_NEAR(seeds[0].x_px, 30 + 50 * 5, 3.0);
}

TEST(ColourSeeds, GivenAColourfulFloor_ThenTheThresholdFollowsTheImageAndNothingStandsOut) {
  // Every pixel a random colour: chroma is high everywhere, so no region is outstanding
  cv::Mat img(240, 320, CV_8UC3);
  cv::RNG rng(7);
  rng.fill(img, cv::RNG::UNIFORM, 0, 256);
  EXPECT_TRUE(colour_blob_seeds(img, 4.0, 120.0).empty());
}

// Brown planks 20 px wide in three shades with dark seams, and sensor noise: a floor whose own
// chroma is high and varies.
cv::Mat plank_floor(cv::Size size, int seed) {
  const cv::Scalar shades[3] = {{60, 100, 160}, {45, 80, 135}, {75, 120, 185}};
  cv::Mat img(size, CV_8UC3);
  for (int x = 0; x < size.width; x += 20)
    cv::rectangle(img, cv::Rect(x, 0, 20, size.height), shades[(x / 20) % 3], cv::FILLED);
  for (int x = 0; x < size.width; x += 20) cv::line(img, {x, 0}, {x, size.height}, {25, 40, 60});
  return with_sensor_noise(img, seed);
}

TEST(ColourSeeds, GivenABallOfAColourTheFloorLacksButNoMoreChroma_ThenRarityAloneSeedsIt) {
  // Given a blue ball on brown planks: its chroma does not stand out from the planks'
  cv::Mat img = plank_floor({320, 240}, 8);
  cv::circle(img, {150, 130}, 12, {170, 90, 40}, cv::FILLED);  // 0.6 % of the image
  ColourSeedParams chroma_only;
  chroma_only.rare_fraction = 0.0;
  const auto by_chroma = colour_blob_seeds(img, 4.0, 120.0, chroma_only);
  EXPECT_TRUE(by_chroma.empty()) << by_chroma.size() << " seed(s) from chroma alone";
  // Then its colour, which no plank has, seeds it
  const auto seeds = colour_blob_seeds(img, 4.0, 120.0);
  ASSERT_EQ(seeds.size(), 1u);
  EXPECT_LT(std::hypot(seeds[0].x_px - 150.0, seeds[0].y_px - 130.0), 4.0);
  EXPECT_NEAR(seeds[0].radius_px, 12.0, 4.0);
  // And a ball of the planks' own colour is not seeded
  cv::Mat brown = plank_floor({320, 240}, 9);
  cv::circle(brown, {150, 130}, 12, {75, 120, 185}, cv::FILLED);
  EXPECT_TRUE(colour_blob_seeds(brown, 4.0, 120.0).empty());
}

TEST(ColourSeeds, GivenRandomColourImagesAndCrops_ThenChromaEqualsMaxMinusMinOfTheSplitPlanes) {
  cv::RNG rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    // Given a random BGR image of any width, or a crop of one (rows with a stride)
    cv::Mat image(17 + trial * 7, 1 + trial * 13, CV_8UC3);
    rng.fill(image, cv::RNG::UNIFORM, 0, 256);
    const cv::Mat bgr = trial % 2 ? image : image(cv::Rect(0, 1, image.cols, image.rows - 2));
    // When its chroma is taken in one pass and by OpenCV's planes
    cv::Mat planes[3], hi, lo;
    cv::split(bgr, planes);
    cv::max(planes[0], planes[1], hi);
    cv::max(hi, planes[2], hi);
    cv::min(planes[0], planes[1], lo);
    cv::min(lo, planes[2], lo);
    // Then they are equal
    EXPECT_EQ(cv::countNonZero(colour_chroma(bgr) != hi - lo), 0) << "trial " << trial;
  }
}

TEST(ColourSeeds, GivenEmptyGreyOrTinyImages_ThenNoSeedsAndNoCrash) {
  EXPECT_TRUE(colour_blob_seeds(cv::Mat(), 4.0, 120.0).empty());
  EXPECT_TRUE(colour_blob_seeds(cv::Mat(240, 320, CV_8UC1, cv::Scalar(90)), 4.0, 120.0).empty());
  EXPECT_TRUE(colour_blob_seeds(cv::Mat(2, 2, CV_8UC3, kPurple), 4.0, 120.0).empty());
}

}  // namespace
}  // namespace stereoball::ball_detector
