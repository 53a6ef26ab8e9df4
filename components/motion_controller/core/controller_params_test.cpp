#include "motion_controller/core/controller_params.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace stereoball::motion_controller {
namespace {

TEST(MotionControllerParams, GivenDefaults_ThenValidAndStaleTimeout300ms) {
  const MotionControllerParams p;
  EXPECT_TRUE(p.validate());
  EXPECT_EQ(p.stale_timeout_ns, 300'000'000);
}

TEST(MotionControllerParams, GivenBadFields_ThenMessageNamesFieldAndRange) {
  MotionControllerParams p;
  p.max_linear_accel_mps2 = 0.0;
  auto err = p.validate();
  ASSERT_FALSE(err);
  EXPECT_NE(err.error().find("max_linear_accel_mps2"), std::string::npos);

  p = MotionControllerParams{};
  p.search_angular_radps = 2.0;  // above max_angular_radps 1.5
  err = p.validate();
  ASSERT_FALSE(err);
  EXPECT_NE(err.error().find("search_angular_radps"), std::string::npos);
  EXPECT_NE(err.error().find("max_angular_radps"), std::string::npos);

  p = MotionControllerParams{};
  p.target_distance_m = std::nan("");
  err = p.validate();
  ASSERT_FALSE(err);
  EXPECT_NE(err.error().find("target_distance_m"), std::string::npos);
}

}  // namespace
}  // namespace stereoball::motion_controller
