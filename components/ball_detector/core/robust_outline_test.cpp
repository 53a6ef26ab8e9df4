// Addition: robust_outline, the outline of a ball partly hidden by a hand and crossed by seams.

#include "ball_detector/core/circle_fit.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <vector>

namespace stereoball::ball_detector {
namespace {

const cv::Scalar kOrange(40, 110, 215);  // BGR
const cv::Scalar kSkin(140, 165, 215);
const cv::Scalar kSeam(25, 25, 30);

// An orange ball of radius r at centre on a grey wall, crossed by black seams (two arcs of
// larger circles and one line, 3 px wide, inside the ball only), its upper right quarter
// hidden by a hand (a skin-coloured block with fingers reaching onto the ball).
cv::Mat held_ball(cv::Size size, cv::Point2d centre, double r) {
  cv::Mat img(size, CV_8UC3, cv::Scalar(120, 125, 128));
  const int shift = 4;  // sub-pixel drawing
  const auto fx = [&](double v) { return static_cast<int>(std::lround(v * (1 << shift))); };
  cv::circle(img, {fx(centre.x), fx(centre.y)}, fx(r), kOrange, cv::FILLED, cv::LINE_AA, shift);
  cv::Mat seams(size, CV_8UC3, cv::Scalar(0, 0, 0));
  seams.setTo(kOrange);
  cv::circle(seams, {fx(centre.x + 1.6 * r), fx(centre.y)}, fx(1.3 * r), kSeam, 3, cv::LINE_AA,
             shift);
  cv::circle(seams, {fx(centre.x - 1.7 * r), fx(centre.y + 0.3 * r)}, fx(1.4 * r), kSeam, 3,
             cv::LINE_AA, shift);
  cv::line(seams, {fx(centre.x - r), fx(centre.y + 0.25 * r)},
           {fx(centre.x + r), fx(centre.y + 0.1 * r)}, kSeam, 3, cv::LINE_AA, shift);
  cv::Mat inside(size, CV_8UC1, cv::Scalar(0));
  cv::circle(inside, {fx(centre.x), fx(centre.y)}, fx(r - 2.0), 255, cv::FILLED, cv::LINE_8, shift);
  seams.copyTo(img, inside);
  // The hand: a palm over the upper right quarter, fingers reaching down onto the ball.
  const cv::Point palm[] = {{fx(centre.x), fx(centre.y - 1.4 * r)},
                            {fx(centre.x + 1.5 * r), fx(centre.y - 1.4 * r)},
                            {fx(centre.x + 1.5 * r), fx(centre.y + 0.05 * r)},
                            {fx(centre.x + 0.8 * r), fx(centre.y - 0.45 * r)},
                            {fx(centre.x + 0.1 * r), fx(centre.y - 0.6 * r)}};
  cv::fillConvexPoly(img, palm, 5, kSkin, cv::LINE_AA, shift);
  for (int f = 0; f < 3; ++f) {
    const double x = centre.x + (0.15 + 0.2 * f) * r;
    cv::line(img, {fx(x), fx(centre.y - 0.6 * r)}, {fx(x - 0.05 * r), fx(centre.y - 0.15 * r)},
             kSkin, static_cast<int>(0.12 * r), cv::LINE_AA, shift);
  }
  cv::GaussianBlur(img, img, {5, 5}, 1.0);
  return img;
}

struct Eye {
  cv::Point2d centre;
  Circle rough;  // what the voting settled on: pulled towards a seam, too small
};

// Given a held ball with seams in both eyes (disparity 24 px) and in each eye a first fit
// pulled off by a fifth of the radius towards the seams and the hand, when the outline is
// searched robustly, then each eye's circle is the ball's within 1.5 px of centre and radius,
// and the disparity within 1.5 px; the first fits were off by more than 6 px.
TEST(RobustOutline, GivenAHeldBallWithSeamsInBothEyesThenEachEyeGetsTheTrueOutline) {
  const double r = 50.0;
  const Eye eyes[] = {{{120.3, 110.6}, {129.0, 116.0, 41.0, 0.0}},
                      {{96.3, 110.6}, {103.5, 104.5, 43.0, 0.0}}};
  std::vector<Circle> found;
  for (const Eye& eye : eyes) {
    const cv::Mat img = held_ball({240, 230}, eye.centre, r);
    EdgeMap e;
    compute_edge_map(img, EdgeParams{}, e);
    ASSERT_GT(std::hypot(eye.rough.x_px - eye.centre.x, eye.rough.y_px - eye.centre.y), 6.0);
    const auto c = robust_outline(e, eye.rough, OutlineSearchParams{});
    ASSERT_TRUE(c.has_value());
    EXPECT_NEAR(c->x_px, eye.centre.x, 1.5);
    EXPECT_NEAR(c->y_px, eye.centre.y, 1.5);
    EXPECT_NEAR(c->radius_px, r, 1.5);
    EXPECT_GT(c->score, outline_coverage(e, eye.rough, OutlineSearchParams{}));
    found.push_back(*c);
  }
  EXPECT_NEAR(found[0].x_px - found[1].x_px, eyes[0].centre.x - eyes[1].centre.x, 1.5);
  EXPECT_NEAR(found[0].y_px, found[1].y_px, 1.5);
}

// Given the true outline as the first fit, when searched robustly, then it is kept (within a
// pixel): the search does not wander onto a seam.
TEST(RobustOutline, GivenTheTrueOutlineThenItIsKept) {
  const cv::Point2d centre(120.3, 110.6);
  const cv::Mat img = held_ball({240, 230}, centre, 50.0);
  EdgeMap e;
  compute_edge_map(img, EdgeParams{}, e);
  const auto c = robust_outline(e, {centre.x, centre.y, 50.0, 0.0}, OutlineSearchParams{});
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->x_px, centre.x, 1.0);
  EXPECT_NEAR(c->y_px, centre.y, 1.0);
  EXPECT_NEAR(c->radius_px, 50.0, 1.0);
}

// Given no usable first fit (zero radius), then nothing.
TEST(RobustOutline, GivenADegenerateRoughCircleThenNothing) {
  EdgeMap e;
  compute_edge_map(cv::Mat(64, 64, CV_8UC3, cv::Scalar(0, 0, 0)), EdgeParams{}, e);
  EXPECT_FALSE(robust_outline(e, {32, 32, 0.0, 0.0}, OutlineSearchParams{}).has_value());
}

}  // namespace
}  // namespace stereoball::ball_detector
