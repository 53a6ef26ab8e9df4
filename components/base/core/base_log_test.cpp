#include "base/core/base_log.hpp"

#include <gtest/gtest.h>

namespace stereoball::base {
namespace {

TEST(BaseLog, CommandLineRoundTrips) {
  // Given a command event with every field set
  BaseEvent e;
  e.kind = BaseEventKind::kCommand;
  e.time_ns = 1'700'000'000'123'456'789;
  e.stamp_ns = 1'700'000'000'100'000'000;
  e.seq = 42;
  e.key_id = 3;
  e.authenticated = true;
  e.estop_engaged = false;
  e.state = GateState::kDriving;
  e.linear_mps = 0.25;
  e.angular_radps = -1.5;
  e.source = "motion controller";  // a space: written as one token
  // When it is written and read back
  auto back = parse_base_event(format_base_event(e));
  // Then every field survives (the space replaced)
  ASSERT_TRUE(back) << back.error();
  EXPECT_EQ(back->kind, BaseEventKind::kCommand);
  EXPECT_EQ(back->time_ns, e.time_ns);
  EXPECT_EQ(back->stamp_ns, e.stamp_ns);
  EXPECT_EQ(back->seq, 42u);
  EXPECT_EQ(back->key_id, 3u);
  EXPECT_TRUE(back->authenticated);
  EXPECT_EQ(back->state, GateState::kDriving);
  EXPECT_DOUBLE_EQ(back->linear_mps, 0.25);
  EXPECT_DOUBLE_EQ(back->angular_radps, -1.5);
  EXPECT_EQ(back->source, "motion_controller");
}

TEST(BaseLog, EstopAndFrameLinesRoundTrip) {
  // Given an e-stop and a frame event
  BaseEvent stop;
  stop.kind = BaseEventKind::kEstop;
  stop.time_ns = 5;
  stop.estop_engaged = true;
  stop.state = GateState::kEmergencyStop;
  BaseEvent frame;
  frame.kind = BaseEventKind::kFrame;
  frame.time_ns = 6;
  frame.linear_mps = 0.5;
  // When read back
  auto s = parse_base_event(format_base_event(stop));
  auto f = parse_base_event(format_base_event(frame));
  // Then kinds, flags and values hold
  ASSERT_TRUE(s) << s.error();
  ASSERT_TRUE(f) << f.error();
  EXPECT_EQ(s->kind, BaseEventKind::kEstop);
  EXPECT_TRUE(s->estop_engaged);
  EXPECT_EQ(s->state, GateState::kEmergencyStop);
  EXPECT_EQ(f->kind, BaseEventKind::kFrame);
  EXPECT_DOUBLE_EQ(f->linear_mps, 0.5);
}

TEST(BaseLog, BadLinesAreErrorsNamingTheProblem) {
  // Given lines that are cut, unknown or carry garbage, Then each is an error naming it
  auto cut = parse_base_event("cmd t=12 estop=0 lin=0");
  ASSERT_FALSE(cut);
  EXPECT_NE(cut.error().find("ang"), std::string::npos);
  auto unknown = parse_base_event("jump t=1");
  ASSERT_FALSE(unknown);
  EXPECT_NE(unknown.error().find("jump"), std::string::npos);
  auto garbage = parse_base_event("frame t=1x estop=0 lin=0 ang=0");
  ASSERT_FALSE(garbage);
  EXPECT_NE(garbage.error().find("'t'"), std::string::npos);
  EXPECT_FALSE(parse_base_event(""));
  EXPECT_FALSE(parse_base_event("estop t=1 estop=1 lin=0 ang=0 state=flying"));
}

}  // namespace
}  // namespace stereoball::base
