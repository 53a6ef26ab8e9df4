#include "camera_server/core/reopen_backoff.hpp"

#include <gtest/gtest.h>

namespace stereoball::camera_server {
namespace {

constexpr int64_t kOneSecondNs = 1'000'000'000;

TEST(ReopenBackoff, GivenRepeatedFailuresWhenScheduledThenWaitDoublesUpToMax) {
  ReopenBackoff b(BackoffParams{0.5, 4.0, 2.0});
  int64_t now = 100 * kOneSecondNs;
  std::vector<int64_t> waits;
  for (int i = 0; i < 6; ++i) {
    const int64_t next = b.on_failure(now);
    waits.push_back(next - now);
    now = next;
  }
  EXPECT_EQ(waits, (std::vector<int64_t>{kOneSecondNs / 2, kOneSecondNs, 2 * kOneSecondNs,
                                         4 * kOneSecondNs, 4 * kOneSecondNs, 4 * kOneSecondNs}));
  EXPECT_EQ(b.failures(), 6u);
}

TEST(ReopenBackoff, GivenScheduledAttemptWhenCheckedThenDueOnlyFromThatTime) {
  ReopenBackoff b(BackoffParams{1.0, 8.0, 2.0});
  const int64_t next = b.on_failure(10 * kOneSecondNs);
  EXPECT_FALSE(b.due(next - 1));
  EXPECT_TRUE(b.due(next));
}

TEST(ReopenBackoff, GivenSuccessAfterFailuresWhenFailingAgainThenStartsFromInitial) {
  ReopenBackoff b(BackoffParams{0.5, 8.0, 2.0});
  b.on_failure(0);
  b.on_failure(0);
  b.on_failure(0);
  b.on_success();
  EXPECT_TRUE(b.due(0));
  EXPECT_EQ(b.on_failure(0), kOneSecondNs / 2);
}

TEST(BackoffParams, GivenMaxBelowInitialWhenValidatedThenNamesMax) {
  BackoffParams p{2.0, 1.0, 2.0};
  ASSERT_FALSE(p.validate().ok());
  EXPECT_NE(p.validate().error().find("max_s"), std::string::npos);
}

}  // namespace
}  // namespace stereoball::camera_server
