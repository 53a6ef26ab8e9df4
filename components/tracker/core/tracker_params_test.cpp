#include "tracker/core/tracker_params.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace stereoball::tracker {
namespace {

TEST(TrackerParams, GivenDefaults_ThenValidAndPaperValues) {
  const TrackerParams p;
  EXPECT_TRUE(p.validate());
  EXPECT_EQ(p.ssd_threshold, 200'000.0);
  EXPECT_EQ(p.register_size, 5);
}

TEST(TrackerParams, GivenBadField_ThenMessageNamesFieldAndRange) {
  TrackerParams p;
  p.register_size = 2;
  auto err = p.validate();
  ASSERT_FALSE(err);
  EXPECT_NE(err.error().find("register_size"), std::string::npos);
  EXPECT_NE(err.error().find("[3, 50]"), std::string::npos);

  p = TrackerParams{};
  p.line_tolerance_m = std::nan("");
  err = p.validate();
  ASSERT_FALSE(err);
  EXPECT_NE(err.error().find("line_tolerance_m"), std::string::npos);

  p = TrackerParams{};
  p.lost_after_ns = 0;
  err = p.validate();
  ASSERT_FALSE(err);
  EXPECT_NE(err.error().find("lost_after_ns"), std::string::npos);

  p = TrackerParams{};
  p.reacquire_positions = 6;  // more than the register holds
  err = p.validate();
  ASSERT_FALSE(err);
  EXPECT_NE(err.error().find("reacquire_positions"), std::string::npos);
  EXPECT_NE(err.error().find("[2, 5]"), std::string::npos);

  p = TrackerParams{};
  p.ssd_threshold = -1.0;
  err = p.validate();
  ASSERT_FALSE(err);
  EXPECT_NE(err.error().find("ssd_threshold"), std::string::npos);
}

}  // namespace
}  // namespace stereoball::tracker
