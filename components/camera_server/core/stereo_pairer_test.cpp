#include "camera_server/core/stereo_pairer.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace stereoball::camera_server {
namespace {

constexpr int64_t kPeriod = 33'333'333;  // 30 Hz

using Pairer = StereoPairer<int>;

EyeFrame<int> left(int64_t t, int id) {
  return {Eye::kLeft, t, id};
}
EyeFrame<int> right(int64_t t, int id) {
  return {Eye::kRight, t, id};
}

Pairer make(int64_t skew_ns = kPeriod / 2) {
  return Pairer(PairerParams{skew_ns, 4});
}

TEST(StereoPairer, GivenInterleavedFramesWithinSkewWhenSteppedThenEveryFramePairs) {
  Pairer p = make();
  std::vector<StereoPair<int>> pairs;
  for (int i = 0; i < 10; ++i) {
    EXPECT_FALSE(p.step(left(i * kPeriod, i)).pair);
    auto r = p.step(right(i * kPeriod + 2'000'000, 100 + i));
    ASSERT_TRUE(r.pair);
    pairs.push_back(*r.pair);
  }
  EXPECT_EQ(p.stats().pairs, 10u);
  EXPECT_EQ(p.stats().dropped_left + p.stats().dropped_right, 0u);
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ(pairs[i].seq, static_cast<uint64_t>(i));
    EXPECT_EQ(pairs[i].left, i);
    EXPECT_EQ(pairs[i].right, 100 + i);
    EXPECT_EQ(pairs[i].stamp_ns, i * kPeriod + 1'000'000);  // mean of both stamps
  }
}

TEST(StereoPairer, GivenSkewExactlyAtLimitWhenSteppedThenPairs) {
  Pairer p = make(5'000'000);
  p.step(left(0, 1));
  EXPECT_TRUE(p.step(right(5'000'000, 2)).pair);
}

TEST(StereoPairer, GivenSkewJustAboveLimitWhenSteppedThenNoPairAndOldFramesDropped) {
  Pairer p = make(5'000'000);
  for (int i = 0; i < 5; ++i) {
    EXPECT_FALSE(p.step(left(i * kPeriod, i)).pair);
    EXPECT_FALSE(p.step(right(i * kPeriod + 5'000'001, i)).pair);
  }
  EXPECT_EQ(p.stats().pairs, 0u);
  // Each new frame makes the older partner-less frame of the other eye unpairable.
  EXPECT_GE(p.stats().dropped_left + p.stats().dropped_right, 8u);
}

TEST(StereoPairer, GivenOneRightFrameLostWhenSteppedThenItsLeftIsDroppedAndTheRestPair) {
  Pairer p = make();
  uint32_t dropped = 0;
  for (int i = 0; i < 6; ++i) {
    dropped += p.step(left(i * kPeriod, i)).dropped;
    if (i == 3) continue;  // right frame 3 never arrives
    auto r = p.step(right(i * kPeriod + 1'000'000, i));
    dropped += r.dropped;
    ASSERT_TRUE(r.pair) << "frame " << i;
    EXPECT_EQ(r.pair->left, i);
  }
  EXPECT_EQ(p.stats().pairs, 5u);
  EXPECT_EQ(p.stats().dropped_left, 1u);
  EXPECT_EQ(p.stats().dropped_right, 0u);
  EXPECT_EQ(dropped, 1u);
}

TEST(StereoPairer, GivenRightStreamDeliveredTwoFramesLateWhenSteppedThenStampsStillPair) {
  Pairer p = make();
  std::vector<std::pair<int, int>> got;
  for (int i = 0; i < 8; ++i) {
    if (auto r = p.step(left(i * kPeriod, i)).pair) got.emplace_back(r->left, r->right);
    if (i >= 2) {
      if (auto r = p.step(right((i - 2) * kPeriod + 500'000, i - 2)).pair) {
        got.emplace_back(r->left, r->right);
      }
    }
  }
  ASSERT_EQ(got.size(), 6u);
  for (size_t k = 0; k < got.size(); ++k) {
    EXPECT_EQ(got[k].first, static_cast<int>(k));
    EXPECT_EQ(got[k].second, static_cast<int>(k));
  }
  EXPECT_EQ(p.stats().dropped_left + p.stats().dropped_right, 0u);
}

TEST(StereoPairer, GivenRightStampCloserToNewerLeftWhenSteppedThenClosestLeftIsChosen) {
  Pairer p = make(kPeriod);  // wide skew: both lefts are candidates
  p.step(left(0, 0));
  p.step(left(kPeriod, 1));
  auto r = p.step(right(kPeriod - 1'000'000, 7));
  ASSERT_TRUE(r.pair);
  EXPECT_EQ(r.pair->left, 1);
  EXPECT_EQ(r.dropped, 1u);  // left 0 can no longer pair
  EXPECT_EQ(p.stats().dropped_left, 1u);
}

TEST(StereoPairer, GivenOneCameraSilentWhenOtherKeepsStreamingThenPendingIsBounded) {
  Pairer p = make();
  for (int i = 0; i < 20; ++i) p.step(left(i * kPeriod, i));
  EXPECT_EQ(p.stats().dropped_left, 16u);  // max_pending = 4 held
  EXPECT_EQ(p.flush(), 4u);
  EXPECT_EQ(p.stats().dropped_left, 20u);
}

TEST(PairerParams, GivenZeroSkewWhenValidatedThenNamesTheField) {
  PairerParams bad{0, 4};
  ASSERT_FALSE(bad.validate().ok());
  EXPECT_NE(bad.validate().error().find("max_skew_ns"), std::string::npos);
  EXPECT_TRUE(PairerParams{}.validate().ok());
}

}  // namespace
}  // namespace stereoball::camera_server
