// The simulator's render lead: the slowest recent frame's work with a margin, within the period.

#include "simulator/core/render_lead.hpp"

#include <gtest/gtest.h>

namespace stereoball::simulator {
namespace {

constexpr int64_t kMs = 1'000'000;
constexpr int64_t kPeriod = 33'333'333;  // 30 Hz

TEST(RenderLead, GivenNoFrameYetThenTheInitialLeadWithinThePeriod) {
  EXPECT_EQ(RenderLead(12 * kMs, kPeriod, 30).lead_ns(), 12 * kMs);
  // A start-up measurement longer than the period is cut to it (less the half margin).
  EXPECT_EQ(RenderLead(50 * kMs, kPeriod, 30).lead_ns(), kPeriod - RenderLead::kMarginNs / 2);
  EXPECT_EQ(RenderLead(0, kPeriod, 30).lead_ns(), RenderLead::kMarginNs);
}

TEST(RenderLead, GivenAStartUpLeadTooLongWhenFramesWorkFastThenTheLeadShrinksToTheirWork) {
  // Given: start-up measured beside the other nodes starting: 30 ms.
  RenderLead lead(30 * kMs, kPeriod, 30);
  // When: the frames' work takes 6-8 ms.
  for (int i = 0; i < 10; ++i) lead.add_work((6 + i % 3) * kMs);
  // Then: 8 ms x 5/4 + the margin.
  EXPECT_EQ(lead.lead_ns(), 12 * kMs);
  EXPECT_EQ(lead.min_lead_ns(), 9'500'000) << "after the first frame alone: 6 ms x 5/4 + 2 ms";
  EXPECT_EQ(lead.max_lead_ns(), 30 * kMs);
}

TEST(RenderLead, GivenOneSlowFrameInTenThenTheLeadFollowsTheOthers) {
  // Given: a second of frames whose work takes 4 ms.
  RenderLead lead(10 * kMs, kPeriod, 30);
  for (int i = 0; i < 30; ++i) lead.add_work(4 * kMs);
  EXPECT_EQ(lead.lead_ns(), 7 * kMs);
  // When: three frames of the second are slowed by other work on the cores.
  for (int i = 0; i < 3; ++i) lead.add_work(12 * kMs);
  // Then: the lead stays with the 90 % of frames (those three are late, not the next renders
  // started beside the frames before them).
  EXPECT_EQ(lead.lead_ns(), 7 * kMs);
  // When: a fourth one is; then more than a tenth is slow and the lead covers them.
  lead.add_work(12 * kMs);
  EXPECT_EQ(lead.lead_ns(), 17 * kMs);
  // When: a second of fast frames follows; then the slow ones have left the window.
  for (int i = 0; i < 30; ++i) lead.add_work(4 * kMs);
  EXPECT_EQ(lead.lead_ns(), 7 * kMs);
}

TEST(RenderLead, GivenWorkLongerThanAPeriodThenTheLeadStopsBelowThePeriod) {
  RenderLead lead(10 * kMs, kPeriod, 30);
  lead.add_work(40 * kMs);
  EXPECT_EQ(lead.lead_ns(), kPeriod - RenderLead::kMarginNs / 2);
}

TEST(RenderLead, GivenANegativeWorkTimeThenItIsIgnored) {
  RenderLead lead(10 * kMs, kPeriod, 30);
  lead.add_work(-5 * kMs);
  EXPECT_EQ(lead.lead_ns(), 10 * kMs);
  lead.add_work(4 * kMs);
  EXPECT_EQ(lead.lead_ns(), 7 * kMs);
}

TEST(RenderLead, GivenAWindowOfZeroThenOneFrameIsKept) {
  RenderLead lead(10 * kMs, kPeriod, 0);
  lead.add_work(8 * kMs);
  lead.add_work(4 * kMs);
  EXPECT_EQ(lead.lead_ns(), 7 * kMs);
}

}  // namespace
}  // namespace stereoball::simulator
