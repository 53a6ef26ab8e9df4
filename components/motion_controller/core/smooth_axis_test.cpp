#include "motion_controller/core/smooth_axis.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace stereoball::motion_controller {
namespace {

constexpr double kDt = 0.05;  // 20 Hz

AxisLimits limits() {
  return {1.0, -0.5, 2.0, 10.0, 2.0};
}

// Speeding up at most 1 m/s^2, braking up to 3 m/s^2.
AxisLimits brakes_harder() {
  return {1.0, -0.5, 1.0, 10.0, 3.0};
}

// Runs the axis toward a target sequence and checks every limit on every step: max_accel
// while the speed grows, max_brake while it drops (or passes zero), and an acceleration above
// the bound that now applies only ramping down from the step before.
void expect_within_limits(const std::vector<double>& targets, const AxisLimits& lim) {
  SmoothAxis axis(lim);
  double v_prev = 0.0;
  double a_prev = 0.0;
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const double v = axis.step(targets[i], kDt);
    const double a = (v - v_prev) / kDt;
    ASSERT_LE(v, lim.max_velocity + 1e-9) << "step " << i;
    ASSERT_GE(v, lim.min_velocity - 1e-9) << "step " << i;
    const bool slowing = std::abs(v) < std::abs(v_prev) || v * v_prev < 0.0;
    const double cap = slowing ? lim.max_brake : lim.max_accel;
    ASSERT_LE(std::abs(a), std::max(cap, std::abs(a_prev)) + 1e-6) << "step " << i;
    ASSERT_LE(std::abs(a), std::max(lim.max_accel, lim.max_brake) + 1e-6) << "step " << i;
    ASSERT_LE(std::abs(a - a_prev) / kDt, lim.max_jerk + 1e-4) << "step " << i;
    v_prev = v;
    a_prev = a;
  }
}

// Steps toward target until the velocity reaches it (at most 400 steps); returns the count.
int steps_to(SmoothAxis& axis, double target) {
  int steps = 0;
  while (std::abs(axis.velocity() - target) > 1e-9 && steps < 400) {
    axis.step(target, kDt);
    ++steps;
  }
  return steps;
}

TEST(SmoothAxis, GivenStepTarget_ThenReachesItWithoutOvershoot) {
  SmoothAxis axis(limits());
  double v = 0.0;
  double peak = 0.0;
  int steps = 0;
  while (std::abs(v - 0.8) > 1e-9 && steps < 200) {
    v = axis.step(0.8, kDt);
    peak = std::max(peak, v);
    ++steps;
  }
  EXPECT_NEAR(v, 0.8, 1e-9);
  EXPECT_LE(peak, 0.8 + 1e-9);
  // 0.8 at 2 m/s^2 needs at least 0.4 s; jerk adds ramp time but not seconds
  EXPECT_GE(steps, 8);
  EXPECT_LE(steps, 20);
  // And one step later the acceleration has ramped out while the velocity holds
  EXPECT_NEAR(axis.step(0.8, kDt), 0.8, 1e-12);
  EXPECT_NEAR(axis.accel(), 0.0, 1e-9);
}

TEST(SmoothAxis, GivenTargetsBeyondLimits_ThenVelocityClamped) {
  SmoothAxis axis(limits());
  for (int i = 0; i < 100; ++i) axis.step(5.0, kDt);
  EXPECT_NEAR(axis.velocity(), 1.0, 1e-9);
  for (int i = 0; i < 100; ++i) axis.step(-5.0, kDt);
  EXPECT_NEAR(axis.velocity(), -0.5, 1e-9);
}

// Full speed ahead, full reverse, and short hops either way, ending at rest.
std::vector<double> steps_and_reversals() {
  std::vector<double> targets;
  for (int i = 0; i < 40; ++i) targets.push_back(1.0);
  for (int i = 0; i < 40; ++i) targets.push_back(-0.5);
  for (int i = 0; i < 10; ++i) targets.push_back(0.3);
  for (int i = 0; i < 3; ++i) targets.push_back(-0.2);
  for (int i = 0; i < 40; ++i) targets.push_back(0.0);
  return targets;
}

// 2000 targets uniform in [-2, 2], beyond the limits both ways.
std::vector<double> random_targets(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  std::vector<double> targets;
  for (int i = 0; i < 2000; ++i) targets.push_back(u(rng));
  return targets;
}

TEST(SmoothAxis, GivenStepsAndReversals_ThenAccelAndJerkNeverExceedLimits) {
  expect_within_limits(steps_and_reversals(), limits());
}

TEST(SmoothAxis, GivenRandomTargets_ThenLimitsHold) {
  expect_within_limits(random_targets(4), limits());
}

TEST(SmoothAxis, GivenHarderBrake_ThenStopsInFewerStepsThanItTookToStartAndNeverReverses) {
  SmoothAxis axis(brakes_harder());
  const int start = steps_to(axis, 0.9);
  ASSERT_NEAR(axis.velocity(), 0.9, 1e-9);
  double lowest = axis.velocity();
  int stop = 0;
  while (std::abs(axis.velocity()) > 1e-9 && stop < 400) {
    lowest = std::min(lowest, axis.step(0.0, kDt));
    ++stop;
  }
  // 0.9 m/s at 1 m/s^2 takes at least 0.9 s; braking at 3 m/s^2 and the jerk ramps ~0.5 s
  EXPECT_GE(start, 18);
  EXPECT_LT(stop, start * 3 / 4);
  EXPECT_GE(lowest, -1e-9);  // stopped, not backed up
}

TEST(SmoothAxis, GivenHarderBrakeAndReversals_ThenEachBoundHoldsInItsDirection) {
  expect_within_limits(steps_and_reversals(), brakes_harder());
  expect_within_limits(random_targets(7), brakes_harder());
}

TEST(SmoothAxis, GivenReset_ThenZeroAtOnce) {
  SmoothAxis axis(limits());
  for (int i = 0; i < 10; ++i) axis.step(1.0, kDt);
  ASSERT_GT(axis.velocity(), 0.3);
  axis.reset();
  EXPECT_EQ(axis.velocity(), 0.0);
  EXPECT_EQ(axis.accel(), 0.0);
}

TEST(SmoothAxis, GivenZeroDt_ThenUnchanged) {
  SmoothAxis axis(limits());
  axis.step(1.0, kDt);
  const double v = axis.velocity();
  EXPECT_EQ(axis.step(1.0, 0.0), v);
}

}  // namespace
}  // namespace stereoball::motion_controller
