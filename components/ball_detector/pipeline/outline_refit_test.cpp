// The pure parts of the checks on a found pair's outlines (outline_refit.hpp): where the other
// eye sees an unmoved ball, and how far a moved pair's two radii may differ.

#include "ball_detector/pipeline/outline_refit.hpp"

#include <gtest/gtest.h>

#include "ball_detector/pipeline/synthetic_pairing_fixture.hpp"

namespace sb = stereoball;
using sb::ball_detector::Circle;

namespace {

class OutlineChecks : public sb::ball_detector::testing::SyntheticPairingTest {
 protected:
  OutlineChecks() : SyntheticPairingTest(0.15) {}

  Circle seen(const cv::Vec3d& c, bool right) const { return outline_in_eye(c, right); }
};

}  // namespace

TEST_F(OutlineChecks, GivenOneEyesOutline_ThenTheUnmovedPartnerIsTheOtherEyesOutline) {
  // Given a ball off the axis, 1.4 m away, as each eye sees it
  const cv::Vec3d ball(0.3, -0.2, 1.4);
  const Circle left = seen(ball, false), right = seen(ball, true);
  // Then each eye's outline predicts the other's (same rows, the size's disparity)
  for (const bool from_right : {true, false}) {
    const auto p =
        sb::ball_detector::unmoved_partner_outline(ctx_, from_right ? right : left, from_right);
    ASSERT_TRUE(p.has_value());
    const Circle& other = from_right ? left : right;
    EXPECT_NEAR(p->x_px, other.x_px, 0.05);
    EXPECT_NEAR(p->y_px, other.y_px, 0.05);
    EXPECT_NEAR(p->radius_px, other.radius_px, 0.05);
  }
  // A circle without a radius predicts nothing
  EXPECT_FALSE(
      sb::ball_detector::unmoved_partner_outline(ctx_, {320, 240, 0.0, 0.9}, true).has_value());
}

TEST_F(OutlineChecks, GivenAMovedPair_ThenItsRadiiMayDifferByTheDepthChangeAndTheTolerance) {
  // Given a ball 1.2 m away, eyes apart by a motion of 0.6 ball radii (6.6 cm of depth)
  ctx_.motion_radii = 0.6;
  const cv::Vec3d ball(0.0, 0.0, 1.2);
  sb::ball_detector::StereoPair pair;
  pair.left = seen(ball, false);
  pair.right = seen(ball, true);
  pair.position_m = ball;
  pair.depth_from_size_m = 1.2;
  const double r = pair.right.radius_px;
  // When the radii agree, they agree; the allowance is r x 0.066 / 1.2 plus 2 px
  auto m = sb::ball_detector::moved_radii(ctx_, pair);
  EXPECT_TRUE(m.agree);
  EXPECT_NEAR(m.difference_px, 0.0, 0.05);
  EXPECT_NEAR(m.allowed_px, r * 0.6 * 0.11 / 1.2 + 2.0, 0.1);
  // When one radius is larger by a little less than that, they still agree
  pair.left.radius_px += 0.9 * m.allowed_px;
  EXPECT_TRUE(sb::ball_detector::moved_radii(ctx_, pair).agree);
  // When by a little more, they are not one ball's
  pair.left.radius_px += 0.2 * m.allowed_px;
  m = sb::ball_detector::moved_radii(ctx_, pair);
  EXPECT_FALSE(m.agree);
  EXPECT_GT(m.difference_px, m.allowed_px);
  // Without motion (synchronised eyes) the fits' tolerance alone is allowed
  ctx_.motion_radii = 0.0;
  EXPECT_NEAR(sb::ball_detector::moved_radii(ctx_, pair).allowed_px, 2.0, 1e-9);
}
