#include "simulator/core/world.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace stereoball::simulator {
namespace {

constexpr int64_t kSecondNs = 1'000'000'000;

SimParams fast_base() {
  SimParams p;
  p.robot.max_linear_accel_mps2 = 1000.0;
  p.robot.max_angular_accel_radps2 = 1000.0;
  p.robot.command_timeout_ns = 10 * kSecondNs;
  return p;
}

Scenario empty_room() {
  Scenario s;
  s.room = RoomSpec{};
  s.room.x_min_m = -10, s.room.x_max_m = 10, s.room.y_min_m = -10, s.room.y_max_m = 10;
  return s;
}

TEST(World, ConstantCommandFollowsTheExpectedArc) {
  // Given a base with negligible acceleration limits at the origin facing +x
  const SimParams p = fast_base();
  const Scenario s = empty_room();
  World w(p, s);
  // When commanded 0.5 m/s and +0.5 rad/s (turn left) for 2 s
  w.set_command({0.5, 0.5, 0});
  w.advance_to(2 * kSecondNs);
  // Then it is on the circle of radius v/w = 1 m centred at (0, 1), turned left by 1 rad
  const RobotState& r = w.robot();
  EXPECT_NEAR(r.x_m, std::sin(1.0), 0.01);
  EXPECT_NEAR(r.y_m, 1.0 - std::cos(1.0), 0.01);
  EXPECT_NEAR(r.yaw_rad, 1.0, 0.01);
  EXPECT_NEAR(r.linear_mps, 0.5, 1e-9);
  EXPECT_NEAR(r.angular_radps, 0.5, 1e-9);
}

TEST(World, AccelerationAndVelocityLimitsApply) {
  // Given a base limited to 1 m/s^2 and 0.4 m/s
  SimParams p;
  p.robot.max_linear_accel_mps2 = 1.0;
  p.robot.max_linear_mps = 0.4;
  p.robot.command_timeout_ns = 10 * kSecondNs;
  const Scenario s = empty_room();
  World w(p, s);
  // When asked for 2 m/s
  w.set_command({2.0, 0.0, 0});
  w.advance_to(kSecondNs / 10);
  // Then after 0.1 s it has reached only 0.1 m/s, and later saturates at 0.4 m/s
  EXPECT_NEAR(w.robot().linear_mps, 0.1, 1e-9);
  w.set_command({2.0, 0.0, kSecondNs / 10});
  w.advance_to(kSecondNs / 2);
  EXPECT_NEAR(w.robot().linear_mps, 0.4, 1e-9);
}

TEST(World, StaleCommandStopsTheBase) {
  // Given a base with a 300 ms command timeout driving forward
  SimParams p = fast_base();
  p.robot.command_timeout_ns = 300'000'000;
  const Scenario s = empty_room();
  World w(p, s);
  w.set_command({0.5, 0.2, 0});
  w.advance_to(200'000'000);
  EXPECT_GT(w.robot().linear_mps, 0.4);
  // When no new command arrives for longer than the timeout
  w.advance_to(kSecondNs);
  const double x = w.robot().x_m;
  w.advance_to(2 * kSecondNs);
  // Then the base has stopped and does not move any more
  EXPECT_EQ(w.robot().linear_mps, 0.0);
  EXPECT_EQ(w.robot().angular_radps, 0.0);
  EXPECT_EQ(w.robot().x_m, x);
}

// Drives a default-limited base (1.5 m/s^2 up, 4 m/s^2 braking) to v, w; returns the time.
int64_t drive_to(World& w, double v_mps, double w_radps) {
  w.set_command({v_mps, w_radps, 0});
  w.advance_to(2 * kSecondNs);
  EXPECT_NEAR(w.robot().linear_mps, v_mps, 1e-9);
  EXPECT_NEAR(w.robot().angular_radps, w_radps, 1e-9);
  return 2 * kSecondNs;
}

TEST(World, ZeroCommandBrakesAtTheBrakeLimitWhileAccelerationStaysAtItsLimit) {
  // Given the default base (accelerates at 1.5 m/s^2, brakes at 4 m/s^2)
  SimParams p;
  p.robot.command_timeout_ns = 10 * kSecondNs;
  ASSERT_DOUBLE_EQ(p.robot.max_linear_accel_mps2, 1.5);
  ASSERT_DOUBLE_EQ(p.robot.max_linear_brake_mps2, 4.0);
  World w(p, empty_room());
  // When it speeds up from rest, then only at 1.5 m/s^2: 0.15 m/s after 0.1 s
  w.set_command({0.8, 0.0, 0});
  w.advance_to(kSecondNs / 10);
  EXPECT_NEAR(w.robot().linear_mps, 0.15, 1e-9);
  const int64_t t0 = drive_to(w, 0.8, 0.0);
  // When commanded zero at 0.8 m/s
  w.set_command({0.0, 0.0, t0});
  const double brake_s = 0.8 / p.robot.max_linear_brake_mps2;  // 0.2 s
  w.advance_to(t0 + static_cast<int64_t>((brake_s - 0.01) * kSecondNs));
  // Then 10 ms before 0.8 / 4 s it is still rolling at 4 m/s^2 * 10 ms
  EXPECT_NEAR(w.robot().linear_mps, 0.04, 1e-6);
  // And one physics step after 0.8 / 4 s it is at rest (at 1.5 m/s^2 it would need 0.53 s)
  w.advance_to(t0 + static_cast<int64_t>(brake_s * kSecondNs) + 2'000'000);
  EXPECT_EQ(w.robot().linear_mps, 0.0);
}

TEST(World, SlowingDownBrakesButReversingAcceleratesPastZero) {
  // Given the default base driving forward at 0.6 m/s
  SimParams p;
  p.robot.command_timeout_ns = 10 * kSecondNs;
  World w(p, empty_room());
  int64_t t = drive_to(w, 0.6, 0.0);
  // When commanded 0.2 m/s, then it slows at the brake limit: 0.2 m/s after 0.1 s
  w.set_command({0.2, 0.0, t});
  w.advance_to(t + kSecondNs / 20);
  EXPECT_NEAR(w.robot().linear_mps, 0.4, 1e-9);
  w.advance_to(t += kSecondNs / 10);
  EXPECT_NEAR(w.robot().linear_mps, 0.2, 1e-9);
  // When commanded -0.5 m/s, then it brakes to zero in 0.05 s and then speeds up backwards
  // at the acceleration limit only: -1.5 m/s^2 * 0.1 s after the stop
  w.set_command({-0.5, 0.0, t});
  w.advance_to(t + kSecondNs / 20 + kSecondNs / 10);
  EXPECT_NEAR(w.robot().linear_mps, -0.15, 1e-9);
  // And braking from reverse is symmetric: -0.5 m/s to rest in 0.125 s
  w.advance_to(t += 2 * kSecondNs);
  w.set_command({0.0, 0.0, t});
  w.advance_to(t + kSecondNs / 10);
  EXPECT_NEAR(w.robot().linear_mps, -0.1, 1e-9);
  w.advance_to(t + kSecondNs / 8 + 2'000'000);
  EXPECT_EQ(w.robot().linear_mps, 0.0);
}

TEST(World, YawRateBrakesAtItsOwnLimit) {
  // Given the default base turning at 1.6 rad/s (6 rad/s^2 up, 16 rad/s^2 braking)
  SimParams p;
  p.robot.command_timeout_ns = 10 * kSecondNs;
  World w(p, empty_room());
  const int64_t t0 = drive_to(w, 0.0, 1.6);
  // When commanded zero, then it is at 1.6 - 16 * 0.05 = 0.8 rad/s after 50 ms, at rest after 0.1 s
  w.set_command({0.0, 0.0, t0});
  w.advance_to(t0 + kSecondNs / 20);
  EXPECT_NEAR(w.robot().angular_radps, 0.8, 1e-9);
  w.advance_to(t0 + kSecondNs / 10 + 2'000'000);
  EXPECT_EQ(w.robot().angular_radps, 0.0);
}

TEST(World, StaleCommandBrakesAtTheBrakeLimit) {
  // Given the default base at 0.8 m/s on a command that will go stale after 300 ms
  SimParams p;
  World w(p, empty_room());
  w.set_command({0.8, 0.0, 0});
  w.advance_to(kSecondNs / 4);  // 0.375 m/s
  const int64_t t0 = 2 * kSecondNs;
  for (int64_t t = kSecondNs / 4; t <= t0; t += kSecondNs / 20) {
    w.set_command({0.8, 0.0, t});
    w.advance_to(t);
  }
  ASSERT_NEAR(w.robot().linear_mps, 0.8, 1e-9);
  // When no command arrives for 300 ms + 0.8 / 4 s, then the base is at rest
  w.advance_to(t0 + 300'000'000);
  EXPECT_NEAR(w.robot().linear_mps, 0.8, 0.01);
  w.advance_to(t0 + 500'000'000 + 4'000'000);
  EXPECT_EQ(w.robot().linear_mps, 0.0);
}

TEST(World, RollingBallDeceleratesAndStops) {
  // Given a ball rolling at 1 m/s with 0.5 m/s^2 rolling deceleration
  SimParams p;
  p.ball.rolling_decel_mps2 = 0.5;
  Scenario s = empty_room();
  s.ball = BallSpec{};
  s.ball->x_m = -5.0, s.ball->y_m = 3.0, s.ball->vx_mps = 1.0;
  World w(p, s);
  // When it rolls until it stops
  w.advance_to(5 * kSecondNs);
  // Then it travelled v^2 / (2a) = 1 m and is at rest
  EXPECT_NEAR(w.ball().position_m.x, -4.0, 1e-6);
  EXPECT_EQ(w.ball().velocity_mps.x, 0.0);
}

TEST(World, BallBouncesOffWallsWithRestitution) {
  // Given a frictionless ball rolling toward the +x wall
  SimParams p;
  p.ball.rolling_decel_mps2 = 0.0;
  p.ball.restitution = 0.5;
  Scenario s = empty_room();
  s.ball = BallSpec{};
  s.ball->x_m = 9.0, s.ball->y_m = 5.0, s.ball->vx_mps = 2.0;
  World w(p, s);
  // When it reaches the wall
  w.advance_to(kSecondNs);
  // Then it comes back at half speed and stays inside the room
  EXPECT_NEAR(w.ball().velocity_mps.x, -1.0, 1e-9);
  EXPECT_LE(w.ball().position_m.x, 10.0 - s.ball->radius_m);
}

TEST(World, KickSetsTheBallVelocityAtItsTime) {
  // Given a still ball with a kick at t = 1 s
  Scenario s = empty_room();
  s.ball = BallSpec{};
  s.ball->x_m = 2.0, s.ball->y_m = 0.0;
  s.kicks.push_back({1.0, 0.0, 1.5});
  const SimParams p;
  World w(p, s);
  // When time passes the kick
  w.advance_to(kSecondNs - 1);
  EXPECT_EQ(w.ball().velocity_mps.y, 0.0);
  w.advance_to(kSecondNs + kSecondNs / 10);
  // Then the ball rolls sideways, and its texture rotates with it
  EXPECT_GT(w.ball().velocity_mps.y, 1.4);
  EXPECT_GT(w.ball().position_m.y, 0.1);
  EXPECT_NE(w.ball().orientation.m[0] + w.ball().orientation.m[4] + w.ball().orientation.m[8], 3.0);
}

}  // namespace
}  // namespace stereoball::simulator
