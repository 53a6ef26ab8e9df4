#include "ball_detector/node/frame_gaps.hpp"

#include <gtest/gtest.h>

namespace stereoball::ball_detector {
namespace {

TEST(FrameGaps, GivenGapsThatEndWhileWaitingThenTheMissingFramesAreLost) {
  // Given frames 0, 1, 4, 5, 9 each handed over after the detector had been idle
  FrameGaps gaps;
  for (uint64_t seq : {0, 1, 4, 5, 9}) gaps.step(seq, true);
  // Then 2 + 3 frames were never received, none replaced
  EXPECT_EQ(gaps.lost(), 5u);
  EXPECT_EQ(gaps.replaced_while_busy(), 0u);
}

TEST(FrameGaps, GivenGapsThatEndInAFrameAlreadyWaitingThenTheyAreReplacedNotLost) {
  // Given a busy detector: frame 3 was waiting when frame 0 was done, 6 when 3 was done
  FrameGaps gaps;
  gaps.step(0, true);
  gaps.step(3, false);
  gaps.step(6, false);
  // Then the 4 frames between were replaced in the one-deep reader, not lost in transport
  EXPECT_EQ(gaps.lost(), 0u);
  EXPECT_EQ(gaps.replaced_while_busy(), 4u);
}

TEST(FrameGaps, GivenTheSourceRestartsWhenSeqGoesBackThenNothingIsCounted) {
  FrameGaps gaps;
  gaps.step(500, true);
  gaps.step(0, true);
  gaps.step(1, true);
  EXPECT_EQ(gaps.lost(), 0u);
  EXPECT_EQ(gaps.replaced_while_busy(), 0u);
}

TEST(FrameGaps, GivenPeriodsWhenTakenThenEachHoldsItsOwnFiguresAndFrequencyIsATenth) {
  // Given a period with 6 received and 62 lost (raw 2304x1296 frames over a 4 MB buffer)
  FrameGaps gaps;
  for (uint64_t seq = 0; seq <= 55; seq += 11) gaps.step(seq, true);
  const FrameGapPeriod bad = gaps.take_period();
  EXPECT_EQ(bad.received, 6u);
  EXPECT_EQ(bad.lost, 50u);  // 5 gaps of 10 (the first frame opens the sequence)
  EXPECT_TRUE(frequent_losses(bad));
  // When the next period receives 30 frames in order, Then it starts from zero
  for (uint64_t seq = 56; seq < 86; ++seq) gaps.step(seq, true);
  const FrameGapPeriod good = gaps.take_period();
  EXPECT_EQ(good.received, 30u);
  EXPECT_EQ(good.lost, 0u);
  EXPECT_FALSE(frequent_losses(good));
  // And one lost frame in 30, or 2 in 30, is not frequent; 4 in 30 is
  EXPECT_FALSE(frequent_losses({29, 1}));
  EXPECT_FALSE(frequent_losses({28, 2}));
  EXPECT_TRUE(frequent_losses({26, 4}));
  EXPECT_EQ(gaps.lost(), 50u);
}

}  // namespace
}  // namespace stereoball::ball_detector
