#include "frame_count.hpp"

#include <gtest/gtest.h>

namespace sbb = stereoball::bench;

namespace {
constexpr int64_t kSec = 1'000'000'000;
}  // namespace

TEST(FrameCount, RateOfTheFramesSinceTheMark) {
  // Given frames 0..30 received at 30 Hz starting 12 h after boot, the mark at frame 30
  sbb::FrameCount count;
  const int64_t t0 = 12 * 3600 * kSec;
  for (uint64_t i = 0; i <= 30; ++i) count.sample(i, t0 + static_cast<int64_t>(i) * kSec / 30);
  count.restart();
  // When ten more frames arrive at 10 Hz
  for (uint64_t i = 31; i <= 40; ++i)
    count.sample(i, t0 + kSec + static_cast<int64_t>(i - 30) * kSec / 10);
  // Then the rate is that of the frames after the mark
  EXPECT_NEAR(count.rate_hz(), 10.0, 1e-9);
}

TEST(FrameCount, AMarkBeforeAnyFrameStartsAtTheFirstFrame) {
  // Given a measurement begun before the first frame arrived (discovery still under way)
  sbb::FrameCount count;
  count.restart();
  EXPECT_EQ(count.rate_hz(), 0.0);
  // When frames 500..520 then arrive at 20 Hz, 12 h after boot
  const int64_t t0 = 12 * 3600 * kSec;
  for (uint64_t i = 500; i <= 520; ++i)
    count.sample(i, t0 + static_cast<int64_t>(i - 500) * kSec / 20);
  // Then the rate is theirs, not their frame number over the time since boot
  EXPECT_NEAR(count.rate_hz(), 20.0, 1e-9);
}

TEST(FrameCount, NoFrameSinceTheMarkIsZero) {
  // Given frames, then a mark, then none (the stream stopped)
  sbb::FrameCount count;
  count.sample(1, kSec);
  count.sample(2, 2 * kSec);
  count.restart();
  // Then nothing flowed during the measurement
  EXPECT_EQ(count.rate_hz(), 0.0);
}
