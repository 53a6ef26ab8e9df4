#include "tracker/core/block_matcher.hpp"

#include <gtest/gtest.h>

namespace stereoball::tracker {
namespace {

TEST(BlockSsd, GivenIdenticalBlocks_ThenZero) {
  Patch a{};
  a.fill(77);
  EXPECT_EQ(block_ssd(a, a), 0);
}

TEST(BlockSsd, GivenOneChannelDiffers_ThenSquareOfDifference) {
  Patch a{};
  Patch b{};
  b[5] = 12;  // pixel 1, blue
  b[kPatchBytes - 1] = 3;
  EXPECT_EQ(block_ssd(a, b), 12 * 12 + 3 * 3);
  EXPECT_EQ(block_ssd(b, a), block_ssd(a, b));
}

TEST(BlockSsd, GivenBlackAndWhite_ThenMaximumWithoutOverflow) {
  Patch black{};
  Patch white{};
  white.fill(255);
  EXPECT_EQ(block_ssd(black, white), static_cast<std::int64_t>(kPatchBytes) * 255 * 255);
}

TEST(BlockMatcher, GivenNoReference_ThenNoSsd) {
  const BlockMatcher m(200'000.0);
  EXPECT_FALSE(m.has_reference());
  EXPECT_FALSE(m.ssd(Patch{}).has_value());
}

TEST(BlockMatcher, GivenReference_WhenStoringNewBlock_ThenComparesAgainstNewBlock) {
  BlockMatcher m(200'000.0);
  Patch a{};
  Patch b{};
  b.fill(10);
  m.store(a);
  EXPECT_EQ(*m.ssd(b), static_cast<std::int64_t>(kPatchBytes) * 100);
  m.store(b);
  EXPECT_EQ(*m.ssd(b), 0);
  m.clear();
  EXPECT_FALSE(m.has_reference());
}

TEST(BlockMatcher, GivenThreshold_ThenMatchIsStrictlyBelow) {
  const BlockMatcher m(200'000.0);
  EXPECT_TRUE(m.is_match(199'999));
  EXPECT_FALSE(m.is_match(200'000));
  EXPECT_FALSE(m.is_match(450'000));
}

}  // namespace
}  // namespace stereoball::tracker
