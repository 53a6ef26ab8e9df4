#include "camera_server/core/eye_skew.hpp"

#include <gtest/gtest.h>

namespace stereoball::camera_server {
namespace {

TEST(EyeSkewStats, GivenPairsOfAPeriodWhenTakenThenMedianAndMaxOfTheMagnitudesInMicroseconds) {
  // Given five pairs whose right eye is 1, 2, 3, 40 ms late or 5 ms early
  EyeSkewStats stats;
  const int64_t t = 1'700'000'000'000'000'000;
  for (int64_t d_ms : {1, 2, -5, 3, 40}) stats.add(t, t + d_ms * 1'000'000);
  // When the period is summarised
  const auto s = stats.take();
  // Then the median is 3 ms and the largest 40 ms, over 5 pairs
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->pairs, 5u);
  EXPECT_EQ(s->p50_us, 3000u);
  EXPECT_EQ(s->max_us, 40000u);
}

TEST(EyeSkewStats, GivenATakenPeriodWhenTakenAgainThenNothingAndANewPeriodStartsEmpty) {
  // Given a period of one synchronised pair, taken
  EyeSkewStats stats;
  stats.add(100, 100);
  ASSERT_TRUE(stats.take().has_value());
  // When nothing is added, Then the next period has no figures
  EXPECT_FALSE(stats.take().has_value());
  // And a new pair counts alone (the old one does not carry over)
  stats.add(0, 7'500);
  const auto s = stats.take();
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->pairs, 1u);
  EXPECT_EQ(s->p50_us, 7u);
  EXPECT_EQ(s->max_us, 7u);
}

TEST(EyeSkewStats, GivenAnEvenCountWhenTakenThenTheUpperMiddleValueIsTheMedian) {
  EyeSkewStats stats;
  for (int64_t us : {10, 20, 30, 40}) stats.add(us * 1000, 0);
  const auto s = stats.take();
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->p50_us, 30u);
  EXPECT_EQ(s->max_us, 40u);
}

}  // namespace
}  // namespace stereoball::camera_server
