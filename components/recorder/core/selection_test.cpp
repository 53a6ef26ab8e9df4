#include "recorder/core/selection.hpp"

#include <gtest/gtest.h>

namespace stereoball::recorder {
namespace {

const std::vector<std::string> kKnown = {"stereo/frame", "ball/track", "cmd/velocity"};

TEST(Selection, GivenAllWithAnExclusionWhenSelectedThenEverythingElseInTableOrder) {
  const auto r = select_topics(kKnown, {}, true, {"stereo/frame"});
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(*r, (std::vector<std::string>{"ball/track", "cmd/velocity"}));
}

TEST(Selection, GivenNamedTopicsWithADuplicateWhenSelectedThenEachOnce) {
  const auto r = select_topics(kKnown, {"cmd/velocity", "ball/track", "cmd/velocity"}, false, {});
  ASSERT_TRUE(r);
  EXPECT_EQ(*r, (std::vector<std::string>{"cmd/velocity", "ball/track"}));
}

TEST(Selection, GivenBadRequestsWhenSelectedThenTheErrorNamesTheProblem) {
  auto r = select_topics(kKnown, {"ball/trak"}, false, {});
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("unknown topic 'ball/trak'"), std::string::npos);
  EXPECT_NE(r.error().find("cmd/velocity"), std::string::npos);  // lists the known ones
  EXPECT_FALSE(select_topics(kKnown, {}, false, {}));
  EXPECT_FALSE(select_topics(kKnown, {"ball/track"}, true, {}));
  EXPECT_FALSE(select_topics(kKnown, {}, true, {"nope"}));
  r = select_topics(kKnown, {"ball/track"}, false, {"ball/track"});
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("excluded"), std::string::npos);
}

TEST(Playback, GivenARateWhenSchedulingThenGapsAreScaled) {
  const PlaybackSchedule s(1'000'000'000, 500, 2.0);
  EXPECT_EQ(s.due_ns(1'000'000'000), 500);
  EXPECT_EQ(s.due_ns(1'100'000'000), 500 + 50'000'000);
  EXPECT_EQ(s.due_ns(999'000'000), 500);  // earlier than the first: due at once
  const PlaybackSchedule slow(0, 0, 0.5);
  EXPECT_EQ(slow.due_ns(10'000'000), 20'000'000);
}

TEST(Playback, GivenBadParamsWhenValidatedThenTheFieldIsNamed) {
  PlaybackParams p;
  EXPECT_TRUE(p.validate().ok());
  p.rate = 0;
  ASSERT_FALSE(p.validate().ok());
  EXPECT_NE(p.validate().error().find("rate"), std::string::npos);
  p = {};
  p.start_offset_s = -1;
  ASSERT_FALSE(p.validate().ok());
  EXPECT_NE(p.validate().error().find("start_offset_s"), std::string::npos);
}

}  // namespace
}  // namespace stereoball::recorder
