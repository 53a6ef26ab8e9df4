#include "tracker/core/statistical_verifier.hpp"

#include <gtest/gtest.h>

#include <random>

#include "tracker/core/tracker_test_support.hpp"

namespace stereoball::tracker {
namespace {

using testing::kFramePeriodNs;

constexpr std::int64_t kT0 = 1'000'000'000'000;

std::int64_t frame(int i) {
  return kT0 + i * kFramePeriodNs;
}

// Five positions of a still ball at (0, 0, 2) with the given offsets along z, metres.
PositionRegister still_ball(double spread_m) {
  PositionRegister reg(5);
  const double dz[5] = {0.0, spread_m, -spread_m, 0.5 * spread_m, -0.5 * spread_m};
  for (int i = 0; i < 5; ++i) reg.push(Eigen::Vector3d(0.0, 0.0, 2.0 + dz[i]), frame(i));
  return reg;
}

// Five positions of a ball moving at 1 m/s along x (3.3 cm per frame).
PositionRegister rolling_ball() {
  PositionRegister reg(5);
  for (int i = 0; i < 5; ++i) reg.push(Eigen::Vector3d(-0.5 + i / 30.0, 0.1, 2.0), frame(i));
  return reg;
}

TEST(StatisticalVerifier, GivenRegisterNotFull_ThenNothingIsAccepted) {
  PositionRegister reg(5);
  for (int i = 0; i < 4; ++i) reg.push(Eigen::Vector3d(0, 0, 2), frame(i));
  const auto c = check_position(reg, Eigen::Vector3d(0, 0, 2), frame(4), TrackerParams{});
  EXPECT_FALSE(c.register_full);
  EXPECT_FALSE(c.accepted);
}

TEST(StatisticalVerifier, GivenStillBall_WhenNewPositionNearMean_ThenAcceptedByMean) {
  const auto reg = still_ball(0.005);
  const auto c = check_position(reg, Eigen::Vector3d(0.003, 0.0, 2.01), frame(5), TrackerParams{});
  EXPECT_TRUE(c.static_cluster);
  EXPECT_TRUE(c.by_mean);
  EXPECT_TRUE(c.accepted);
}

TEST(StatisticalVerifier, GivenNoiseOnlyCluster_ThenFloorKeepsNoiseFromBeingRejected) {
  // Given a very tight cluster (sigma ~1 mm) and the floor max(3 cm, 2% of 2 m) = 4 cm
  const auto reg = still_ball(0.001);
  TrackerParams p;
  // When a sample 3.5 cm away arrives (plausible depth noise at 2 m)
  const auto near = check_position(reg, Eigen::Vector3d(0, 0, 2.035), frame(5), p);
  // Then it is accepted by the mean test through the floor
  EXPECT_LT(near.sigma_m, 0.002);
  EXPECT_NEAR(near.mean_radius_m, 0.04, 1e-9);
  EXPECT_TRUE(near.by_mean);
  // And without the floor the same sample would fail the mean test
  p.sigma_floor_m = 0.0;
  p.sigma_floor_fraction = 0.0;
  const auto no_floor = check_position(reg, Eigen::Vector3d(0.01, 0, 2.035), frame(5), p);
  EXPECT_FALSE(no_floor.by_mean);
}

TEST(StatisticalVerifier, GivenStillBall_WhenPositionFarFromMeanAndLine_ThenRejected) {
  const auto reg = still_ball(0.005);
  const auto c = check_position(reg, Eigen::Vector3d(0.08, 0.0, 2.0), frame(5), TrackerParams{});
  EXPECT_FALSE(c.by_mean);
  EXPECT_FALSE(c.by_line);
  EXPECT_FALSE(c.accepted);
  EXPECT_NEAR(c.distance_to_mean_m, 0.08, 1e-3);
}

TEST(StatisticalVerifier, GivenRollingBall_WhenNextPositionOnLine_ThenAcceptedByLineNotMean) {
  const auto reg = rolling_ball();
  const auto c =
      check_position(reg, Eigen::Vector3d(-0.5 + 5 / 30.0, 0.1, 2.0), frame(5), TrackerParams{});
  EXPECT_TRUE(c.clean_line);
  EXPECT_TRUE(c.by_line);
  EXPECT_FALSE(c.by_mean);  // the next point is 3 spacings from the mean, sigma is 1.4
  EXPECT_TRUE(c.accepted);
}

TEST(StatisticalVerifier, GivenRollingBall_WhenPositionOffTheLine_ThenRejected) {
  const auto reg = rolling_ball();
  const auto c =
      check_position(reg, Eigen::Vector3d(-0.5 + 5 / 30.0, 0.1, 2.15), frame(5), TrackerParams{});
  EXPECT_GT(c.distance_to_line_m, 0.1);
  EXPECT_FALSE(c.accepted);
}

TEST(StatisticalVerifier, GivenRollingBall_WhenPositionOnLineButTooFarAhead_ThenRejected) {
  // 1 m further along the line in one frame is 30 m/s: not a ball.
  const auto reg = rolling_ball();
  const auto c = check_position(reg, Eigen::Vector3d(0.8, 0.1, 2.0), frame(5), TrackerParams{});
  EXPECT_LT(c.distance_to_line_m, 1e-6);
  EXPECT_FALSE(c.jump_plausible);
  EXPECT_FALSE(c.accepted);
}

TEST(StatisticalVerifier, GivenRandomClutterInRegister_WhenPositionAtItsMean_ThenRejected) {
  // Given five random clutter positions: the register describes no ball
  std::mt19937 rng(7);
  int accepted = 0;
  for (int trial = 0; trial < 200; ++trial) {
    PositionRegister reg(5);
    for (int i = 0; i < 5; ++i) reg.push(testing::clutter_position(rng), frame(i));
    // When the next position is exactly the mean (the most favourable point)
    const auto mean = reg.stats()->mean_m;
    const auto c = check_position(reg, mean, frame(5), TrackerParams{});
    accepted += c.accepted ? 1 : 0;
  }
  // Then it is (almost) never accepted, unlike the bare one-sigma test
  EXPECT_LE(accepted, 2);
}

TEST(StatisticalVerifier, GivenImplausibleStepInsideRegister_ThenRegisterIsNotUsable) {
  // Given a line where one step is 2 m in one frame
  PositionRegister reg(5);
  const double xs[5] = {0.0, 0.03, 0.06, 2.06, 2.09};
  for (int i = 0; i < 5; ++i) reg.push(Eigen::Vector3d(xs[i], 0, 2), frame(i));
  const auto c = check_position(reg, Eigen::Vector3d(2.12, 0, 2), frame(5), TrackerParams{});
  EXPECT_FALSE(c.steps_plausible);
  EXPECT_FALSE(c.accepted);
}

TEST(StatisticalVerifier, GivenIdenticalPositions_ThenNoLineDirectionAndOnlyMeanTestApplies) {
  // Given five identical positions: the covariance is zero, any axis is "principal"
  PositionRegister reg(5);
  for (int i = 0; i < 5; ++i) reg.push(Eigen::Vector3d(0, 0, 2), frame(i));
  TrackerParams p;
  p.jump_margin_m = 1.0;
  // When positions 0.2 m away along each axis arrive
  for (int axis = 0; axis < 3; ++axis) {
    Eigen::Vector3d q(0, 0, 2);
    q(axis) += 0.2;
    const auto c = check_position(reg, q, frame(5), p);
    // Then the degenerate line never accepts them
    EXPECT_FALSE(c.clean_line) << "axis " << axis;
    EXPECT_FALSE(c.accepted) << "axis " << axis;
  }
}

// A rolling ball register where the positions at the given indices are clutter.
PositionRegister rolling_with_strays(std::initializer_list<int> stray) {
  PositionRegister reg(5);
  for (int i = 0; i < 5; ++i) {
    Eigen::Vector3d p(-0.5 + i / 30.0, 0.1, 2.0);
    for (const int s : stray) {
      if (s == i) p = Eigen::Vector3d(1.4, -0.3, 3.5 - 0.4 * i);
    }
    reg.push(p, frame(i));
  }
  return reg;
}

TEST(StatisticalVerifier, GivenOneStrayInRegister_WhenOneOutlierAllowed_ThenJudgedWithoutIt) {
  for (const int stray : {0, 2, 4}) {
    const auto reg = rolling_with_strays({stray});
    const Eigen::Vector3d next(-0.5 + 5 / 30.0, 0.1, 2.0);
    // Without the allowance the spoiled register accepts nothing
    const auto strict = check_position(reg, next, frame(5), TrackerParams{}, 0);
    EXPECT_FALSE(strict.accepted) << "stray " << stray;
    // With it, the four ball positions accept the next ball position
    const auto lenient = check_position(reg, next, frame(5), TrackerParams{}, 1);
    EXPECT_TRUE(lenient.accepted) << "stray " << stray << ": " << lenient.reason;
    EXPECT_EQ(lenient.outlier_left_out, stray);
    // And still reject clutter
    EXPECT_FALSE(
        check_position(reg, Eigen::Vector3d(0.4, 0.3, 2.6), frame(5), TrackerParams{}, 1).accepted);
  }
}

// A register of a rolling ball with one detection 12 cm off its path (a mis-paired frame):
// its line still passes as clean, and the stray tilts it.
TEST(StatisticalVerifier,
     GivenOneStrayTheCleanLineHides_WhenOneOutlierAllowed_ThenJudgedWithoutIt) {
  for (const int stray : {1, 2, 3, 4}) {
    PositionRegister reg(5);
    for (int i = 0; i < 5; ++i)
      reg.push(Eigen::Vector3d(-0.5 + i / 30.0, 0.1, 2.0 + (i == stray ? 0.12 : 0.0)), frame(i));
    const Eigen::Vector3d next(-0.5 + 6 / 30.0, 0.1, 2.0);
    const auto strict = check_position(reg, next, frame(6), TrackerParams{}, 0);
    // The register as it is passes as a line (not "inconsistent") and rejects the ball
    ASSERT_LE(strict.line_rms_m, TrackerParams{}.line_tolerance_m) << "stray " << stray;
    EXPECT_FALSE(strict.accepted) << "stray " << stray << ": " << strict.reason;
    const auto lenient = check_position(reg, next, frame(6), TrackerParams{}, 1);
    EXPECT_TRUE(lenient.accepted) << "stray " << stray << ": " << lenient.reason;
    EXPECT_EQ(lenient.outlier_left_out, stray);
    // A position 15 cm off the four good ones' path (across the stray's offset) is still refused
    EXPECT_FALSE(check_position(reg, Eigen::Vector3d(-0.5 + 6 / 30.0, 0.25, 2.0), frame(6),
                                TrackerParams{}, 1)
                     .accepted)
        << "stray " << stray;
  }
}

TEST(StatisticalVerifier, GivenTwoStraysInRegister_ThenNothingAccepted) {
  const auto reg = rolling_with_strays({1, 3});
  const auto c =
      check_position(reg, Eigen::Vector3d(-0.5 + 5 / 30.0, 0.1, 2.0), frame(5), TrackerParams{}, 1);
  EXPECT_FALSE(c.accepted);
  EXPECT_EQ(c.outlier_left_out, -1);
}

TEST(StatisticalVerifier, GivenConsistentRegister_WhenPositionFar_ThenNoPositionIsLeftOut) {
  // Leaving a good position out must never turn a rejection into an acceptance
  const auto reg = rolling_ball();
  const auto c =
      check_position(reg, Eigen::Vector3d(-0.5 + 5 / 30.0, 0.1, 2.2), frame(5), TrackerParams{}, 1);
  EXPECT_FALSE(c.accepted);
  EXPECT_EQ(c.outlier_left_out, -1);
}

TEST(MaxJump, GivenTime_ThenMarginPlusSpeedTimesTime) {
  TrackerParams p;
  p.jump_margin_m = 0.1;
  p.max_ball_speed_mps = 2.0;
  EXPECT_NEAR(max_jump_m(p, 500'000'000), 1.1, 1e-12);
  EXPECT_NEAR(max_jump_m(p, -5), 0.1, 1e-12);  // out-of-order stamps never widen the gate
}

}  // namespace
}  // namespace stereoball::tracker
