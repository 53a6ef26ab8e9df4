// The image with its brightness removed (remove_brightness) and the seed search on it, on
// hand-built images: grey carpet whose brightness texture drowns a ball's hue-only rim.

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>

#include "ball_detector/core/edge_map.hpp"
#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/core/synthetic.hpp"

namespace stereoball::ball_detector {
namespace {

const Circle kBall{160.0, 120.0, 20.0, 0.0};

// Grey carpet: 2x2 px flecks of random brightness 50-130, no hue, and sensor noise.
cv::Mat grey_carpet(cv::Size size, int seed) {
  cv::RNG rng(static_cast<std::uint64_t>(seed));
  cv::Mat img(size, CV_8UC3);
  for (int y = 0; y < size.height; y += 2)
    for (int x = 0; x < size.width; x += 2) {
      const int v = rng.uniform(50, 131);
      cv::rectangle(img, cv::Rect(x, y, 2, 2), cv::Scalar(v, v, v), cv::FILLED);
    }
  return with_sensor_noise(img, seed);
}

// A dull lilac ball of the carpet's mean brightness (B, G, R = 98, 78, 96 against 90 grey):
// it differs from the carpet in hue by 8-12 levels per channel, in brightness not at all.
void draw_lilac_ball(cv::Mat& img, const Circle& c) {
  cv::circle(img, {static_cast<int>(c.x_px), static_cast<int>(c.y_px)},
             static_cast<int>(c.radius_px), {98, 78, 96}, cv::FILLED);
}

// The closest circle of found to want, or one far off when found is empty.
Circle closest(const std::vector<Circle>& found, const Circle& want) {
  Circle best{1e9, 1e9, 0.0, 0.0};
  for (const Circle& c : found)
    if (std::hypot(c.x_px - want.x_px, c.y_px - want.y_px) <
        std::hypot(best.x_px - want.x_px, best.y_px - want.y_px))
      best = c;
  return best;
}

TEST(RemoveBrightness, GivenGreysOfAnyBrightness_ThenMidGrey_AndHueStepsKeepTheirSignAndGrow) {
  cv::Mat img(1, 5, CV_8UC3);
  img.at<cv::Vec3b>(0, 0) = {0, 0, 0};
  img.at<cv::Vec3b>(0, 1) = {90, 90, 90};
  img.at<cv::Vec3b>(0, 2) = {255, 255, 255};
  img.at<cv::Vec3b>(0, 3) = {98, 78, 96};  // dull lilac, mean 90.7
  img.at<cv::Vec3b>(0, 4) = {0, 0, 255};   // pure red: clips on the far side only
  cv::Mat out;
  remove_brightness(img, out);
  ASSERT_EQ(out.type(), CV_8UC3);
  for (int x = 0; x < 3; ++x) EXPECT_EQ(out.at<cv::Vec3b>(0, x), cv::Vec3b(128, 128, 128)) << x;
  // 128 + 2 * (channel - mean), truncated towards 128: G is 128 + 2 * (78 - 90.67) = 102.7
  EXPECT_EQ(out.at<cv::Vec3b>(0, 3), cv::Vec3b(142, 103, 138));
  EXPECT_EQ(out.at<cv::Vec3b>(0, 4), cv::Vec3b(0, 0, 255));
}

TEST(RemoveBrightness, GivenACrop_ThenTheSameAsTheWholeImageThere) {
  cv::Mat img(40, 50, CV_8UC3);
  cv::RNG(5).fill(img, cv::RNG::UNIFORM, 0, 256);
  cv::Mat whole, crop;
  remove_brightness(img, whole);
  const cv::Rect box(7, 3, 21, 30);
  remove_brightness(img(box), crop);
  EXPECT_EQ(cv::countNonZero(cv::Mat(whole(box) != crop).reshape(1)), 0);
}

TEST(DetectAtSeedsWithoutBrightness,
     GivenAHueOnlyRimOnGreyCarpet_ThenOnlyTheBrightnessFreeEdgesGiveItsOutline) {
  // Given a lilac ball of the carpet's brightness, and a seed 3 px off it (as colour seeds are)
  cv::Mat img = grey_carpet({320, 240}, 1);
  draw_lilac_ball(img, kBall);
  const Circle seed{kBall.x_px + 2.0, kBall.y_px - 2.0, kBall.radius_px + 1.0, 0.0};
  PixelToPixelDetector det{PixelToPixelParams{}};
  // When the seed is refined on the image's own edges (its thresholds from the whole image)
  EdgeMap scratch;
  const EdgeThresholds frame = measure_edge_thresholds(img, PixelToPixelParams{}.edge, scratch);
  const auto on_edges = det.detect_at_seeds(img, frame, {}, {&seed, 1});
  // Then the carpet's flecks drown the rim: no outline there
  const Circle plain = closest(on_edges, kBall);
  EXPECT_GT(std::hypot(plain.x_px - kBall.x_px, plain.y_px - kBall.y_px), 1.0)
      << "found on the plain edges, score " << plain.score;
  // When it is refined on a box around it with the brightness removed
  const cv::Rect box(120, 80, 80, 80);
  const Circle seed_in_box{seed.x_px - box.x, seed.y_px - box.y, seed.radius_px, 0.0};
  const auto found = det.detect_at_seeds_without_brightness(img(box), {}, {&seed_in_box, 1});
  // Then the outline, within a pixel, in the box's coordinates
  ASSERT_EQ(found.size(), 1u);
  EXPECT_NEAR(found[0].x_px + box.x, kBall.x_px, 1.0);
  EXPECT_NEAR(found[0].y_px + box.y, kBall.y_px, 1.0);
  EXPECT_NEAR(found[0].radius_px, kBall.radius_px, 1.0);
  EXPECT_GE(found[0].score, PixelToPixelParams{}.min_score);
  // And its edge map knows the box is a crop of the camera image (the border rule, the camera)
  EXPECT_EQ(det.edge_map().frame_px, cv::Rect2d(-box.x, -box.y, img.cols, img.rows));
}

TEST(DetectAtSeedsWithoutBrightness, GivenAGreyBallOnTheCarpetOrAGreyImage_ThenNothing) {
  // A grey ball as bright as the carpet: no hue, so nothing is left of it without brightness
  cv::Mat img = grey_carpet({320, 240}, 2);
  cv::circle(img, {160, 120}, 20, {90, 90, 90}, cv::FILLED);
  PixelToPixelDetector det{PixelToPixelParams{}};
  const cv::Rect box(120, 80, 80, 80);
  const Circle seed{40.0, 40.0, 20.0, 0.0};
  EXPECT_TRUE(det.detect_at_seeds_without_brightness(img(box), {}, {&seed, 1}).empty());
  // Grey input (a mono camera) has no colour to look at
  cv::Mat grey;
  cv::cvtColor(img, grey, cv::COLOR_BGR2GRAY);
  EXPECT_TRUE(det.detect_at_seeds_without_brightness(grey(box), {}, {&seed, 1}).empty());
}

}  // namespace
}  // namespace stereoball::ball_detector
