#include "tracker/core/position_register.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace stereoball::tracker {
namespace {

TEST(PositionRegister, GivenFullRegister_WhenPushing_ThenOldestIsDropped) {
  PositionRegister reg(3);
  for (int i = 0; i < 5; ++i) reg.push(Eigen::Vector3d(i, 0, 0), i);
  ASSERT_TRUE(reg.full());
  ASSERT_EQ(reg.size(), 3);
  EXPECT_EQ(reg.entries().front().position_m.x(), 2.0);
  EXPECT_EQ(reg.entries().back().position_m.x(), 4.0);
  EXPECT_EQ(reg.entries().back().stamp_ns, 4);
}

TEST(PositionRegister, GivenOnePosition_ThenNoStats) {
  PositionRegister reg(5);
  reg.push(Eigen::Vector3d(1, 2, 3), 0);
  EXPECT_FALSE(reg.stats().has_value());
}

TEST(PositionRegister, GivenTwoPoints_ThenMeanSigmaAndLineAreExact) {
  // Given points 2 m apart along x
  PositionRegister reg(5);
  reg.push(Eigen::Vector3d(0, 0, 1), 0);
  reg.push(Eigen::Vector3d(2, 0, 1), 1);
  // When
  const auto s = reg.stats();
  // Then mean in between, population variance 1 m^2, direction along x, no residual
  ASSERT_TRUE(s.has_value());
  EXPECT_NEAR((s->mean_m - Eigen::Vector3d(1, 0, 1)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(s->sigma_m, 1.0, 1e-12);
  EXPECT_NEAR(std::abs(s->line_direction.x()), 1.0, 1e-9);
  EXPECT_NEAR(s->line_rms_m, 0.0, 1e-9);
  EXPECT_NEAR(s->line_extent_m, 1.0, 1e-9);
}

TEST(PositionRegister, GivenPointsZigZaggingAroundLine_ThenLineRmsIsTheOffset) {
  // Given y offsets of +-0.1 m uncorrelated with x
  PositionRegister reg(4);
  reg.push(Eigen::Vector3d(0, 0.1, 2), 0);
  reg.push(Eigen::Vector3d(1, -0.1, 2), 1);
  reg.push(Eigen::Vector3d(2, -0.1, 2), 2);
  reg.push(Eigen::Vector3d(3, 0.1, 2), 3);
  const auto s = reg.stats();
  ASSERT_TRUE(s.has_value());
  // Then the line runs along x and the residual is exactly 0.1 m
  EXPECT_NEAR(std::abs(s->line_direction.x()), 1.0, 1e-9);
  EXPECT_NEAR(s->line_rms_m, 0.1, 1e-9);
  EXPECT_NEAR(s->sigma_m, std::sqrt(1.25 + 0.01), 1e-9);
}

TEST(DistanceToLine, GivenPointOffLine_ThenPerpendicularDistance) {
  const Eigen::Vector3d dir = Eigen::Vector3d(1, 1, 0).normalized();
  EXPECT_NEAR(distance_to_line(Eigen::Vector3d(5, 5, 0), Eigen::Vector3d::Zero(), dir), 0.0, 1e-12);
  EXPECT_NEAR(distance_to_line(Eigen::Vector3d(7, 7, 0.5), Eigen::Vector3d::Zero(), dir), 0.5,
              1e-12);
  EXPECT_NEAR(distance_to_line(Eigen::Vector3d(1, -1, 0), Eigen::Vector3d::Zero(), dir),
              std::sqrt(2.0), 1e-12);
}

}  // namespace
}  // namespace stereoball::tracker
