#include "motion_controller/core/own_motion.hpp"

#include <gtest/gtest.h>

namespace stereoball::motion_controller {
namespace {

constexpr std::int64_t kMs = 1'000'000;

TEST(OwnMotionHistory, GivenConstantVelocity_ThenTheWeightedMeanIsThatVelocity) {
  // Given 0.5 m/s and 1.0 rad/s in force since before the span
  OwnMotionHistory h;
  h.record(0, {0.5, 1.0});
  // Then any span inside averages to it
  const Velocity v = h.slope_weighted_mean(100 * kMs, 600 * kMs);
  EXPECT_NEAR(v.linear_mps, 0.5, 1e-12);
  EXPECT_NEAR(v.angular_radps, 1.0, 1e-12);
}

TEST(OwnMotionHistory, GivenTurnStartingHalfWay_ThenHalfTheRateBySymmetricWeights) {
  // Given nothing recorded before 500 ms (zero), then 1 rad/s, averaged over 0..1000 ms
  OwnMotionHistory h;
  h.record(500 * kMs, {0.0, 1.0});
  // Then the (t - from)(to - t) weights are symmetric: half the rate
  EXPECT_NEAR(h.slope_weighted_mean(0, 1000 * kMs).angular_radps, 0.5, 1e-12);
}

TEST(OwnMotionHistory, GivenStepInTheSpan_ThenTheMiddleWeighsMoreThanTheEnds) {
  // Given 1 rad/s then 3 rad/s from 800 ms, over 0..1000 ms
  OwnMotionHistory h;
  h.record(0, {0.0, 1.0});
  h.record(800 * kMs, {0.0, 3.0});
  const double mean = h.slope_weighted_mean(0, 1000 * kMs).angular_radps;
  // Then the late step counts less than its 20 % share of time (weights fall to 0 at the end):
  // 1 + 2 * (1 - (3 * 0.8^2 - 2 * 0.8^3)) = 1.208
  EXPECT_NEAR(mean, 1.0 + 2.0 * (1.0 - (3 * 0.64 - 2 * 0.512)), 1e-9);
  EXPECT_LT(mean, 1.0 + 2.0 * 0.2);
}

TEST(OwnMotionHistory, GivenEmptySpanOrForgottenPast_ThenVelocityInForce) {
  // Given three commands, the older ones forgotten up to 250 ms
  OwnMotionHistory h;
  h.record(0, {0.1, 0.0});
  h.record(100 * kMs, {0.2, 0.0});
  h.record(300 * kMs, {0.3, 0.0});
  h.forget_before(250 * kMs);
  // Then the command in force at 250 ms is kept, and an empty span gives the value in force
  EXPECT_NEAR(h.at(250 * kMs).linear_mps, 0.2, 1e-12);
  EXPECT_NEAR(h.slope_weighted_mean(350 * kMs, 350 * kMs).linear_mps, 0.3, 1e-12);
  EXPECT_NEAR(h.at(350 * kMs).linear_mps, 0.3, 1e-12);
}

TEST(OwnMotionHistory, GivenStep_ThenThePlainMeanIsTheTimeShare) {
  // Given 1 rad/s then 3 rad/s from 800 ms, over 0..1000 ms
  OwnMotionHistory h;
  h.record(0, {0.0, 1.0});
  h.record(800 * kMs, {0.0, 3.0});
  // Then the plain mean weighs by time: 0.8 * 1 + 0.2 * 3
  EXPECT_NEAR(h.mean(0, 1000 * kMs).angular_radps, 1.4, 1e-9);
}

}  // namespace
}  // namespace stereoball::motion_controller
