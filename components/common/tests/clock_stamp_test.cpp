#include "common/util/clock_stamp.hpp"

#include <gtest/gtest.h>

namespace stereoball {
namespace {

TEST(ClockStamp, GivenMonotonicStampBeforeNow_ThenSameDistanceBeforeNowOnTheEpochClock) {
  // Given "now" on both clocks, and a stamp 12.345678 ms before now on the monotonic clock
  const std::int64_t now_mono = 8'123'456'789'012;
  const std::int64_t now_epoch = 1'733'123'456'789'012'345;  // needs all 64 bits
  // When it is moved to the epoch clock
  const std::int64_t epoch = monotonic_to_epoch_ns(now_mono - 12'345'678, now_mono, now_epoch);
  // Then it lies exactly as far before "now" there, to the nanosecond
  EXPECT_EQ(epoch, now_epoch - 12'345'678);
  EXPECT_EQ(monotonic_to_epoch_ns(now_mono, now_mono, now_epoch), now_epoch);
}

}  // namespace
}  // namespace stereoball
