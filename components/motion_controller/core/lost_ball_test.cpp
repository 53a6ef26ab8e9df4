#include "motion_controller/core/lost_ball.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace stereoball::motion_controller {
namespace {

TEST(PlaneVelocity, GivenBearingAndRangeRates_ThenTheVelocityTheyCameFrom) {
  for (const PlaneVector p :
       {PlaneVector{0.3, 1.2}, PlaneVector{-0.8, 0.4}, PlaneVector{0.05, -0.6}})
    for (const PlaneVector v :
         {PlaneVector{0.5, -0.2}, PlaneVector{-1.0, 0.9}, PlaneVector{0.0, 0.0}}) {
      const PlaneVector back = plane_velocity(p, polar_rates(p.x, p.z, v.x, v.z));
      EXPECT_NEAR(back.x, v.x, 1e-9);
      EXPECT_NEAR(back.z, v.z, 1e-9);
    }
}

TEST(PlaneVelocity, GivenPointAtTheOrigin_ThenZeroNotNaN) {
  const PlaneVector v = plane_velocity({0.0, 0.0}, {1.0, 2.0});
  EXPECT_EQ(v.x, 0.0);
  EXPECT_EQ(v.z, 0.0);
}

TEST(PredictLostBall, GivenBallRollingLeftAndRobotStill_ThenMovedOnByItsVelocity) {
  LostBall b;
  b.last_m = {0.1, 1.0};
  b.seen_velocity_mps = {-1.0, 0.0};
  b.age_s = 0.4;
  const PlaneVector now = predict_lost_ball(b);
  EXPECT_NEAR(now.x, -0.3, 1e-9);
  EXPECT_NEAR(now.z, 1.0, 1e-9);
}

TEST(PredictLostBall, GivenStillBallAndRobotTurningLeft_ThenTheBallSwingsRightByTheTurn) {
  // Given a ball standing 0.5 m right, 1 m ahead, which the camera saw sweep by only because
  // the robot turned left at 0.5 rad/s, as it still does for 1 s after the loss
  const Velocity turning{0.0, 0.5};
  LostBall b;
  b.last_m = {0.5, 1.0};
  b.seen_velocity_mps = {0.5 * 1.0, -0.5 * 0.5};
  b.own_while_seen = turning;
  b.own_since = turning;
  b.age_s = 1.0;
  const PlaneVector now = predict_lost_ball(b);
  // Then it is where it stood, seen from axes turned 0.5 rad to the left
  EXPECT_NEAR(now.x, 0.5 * std::cos(0.5) + 1.0 * std::sin(0.5), 1e-9);
  EXPECT_NEAR(now.z, -0.5 * std::sin(0.5) + 1.0 * std::cos(0.5), 1e-9);
}

TEST(PredictLostBall, GivenStillBallAndRobotDrivingAtIt_ThenOnlyTheRangeShrinks) {
  const Velocity driving{0.5, 0.0};
  LostBall b;
  b.last_m = {0.2, 2.0};
  b.seen_velocity_mps = {0.0, -0.5};
  b.own_while_seen = driving;
  b.own_since = driving;
  b.age_s = 1.0;
  const PlaneVector now = predict_lost_ball(b);
  EXPECT_NEAR(now.x, 0.2, 1e-9);
  EXPECT_NEAR(now.z, 1.5, 1e-9);
}

TEST(PredictLostBall, GivenRobotDrivingAnArc_ThenAStillBallIsWhereTheArcLeavesIt) {
  // Given a still ball 1 m ahead and a robot driving a quarter circle of radius 1 m to the left
  // (1 m/s, 1 rad/s for pi/2 s): it ends 1 m left of and 1 m ahead of its start, facing left
  const Velocity arc{1.0, 1.0};
  LostBall b;
  b.last_m = {0.0, 1.0};
  b.seen_velocity_mps = {1.0 * 1.0, -1.0};
  b.own_while_seen = arc;
  b.own_since = arc;
  b.age_s = std::numbers::pi / 2.0;
  const PlaneVector now = predict_lost_ball(b);
  // Then the ball, ahead of where it started, is straight behind it
  EXPECT_NEAR(now.x, 0.0, 1e-9);
  EXPECT_NEAR(now.z, -1.0, 1e-9);
}

}  // namespace
}  // namespace stereoball::motion_controller
