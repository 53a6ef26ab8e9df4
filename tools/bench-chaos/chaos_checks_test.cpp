#include "chaos_checks.hpp"

#include <gtest/gtest.h>

#include <set>

#include "chaos_plan.hpp"

namespace stereoball::bench_chaos {
namespace {

using base::BaseEvent;
using base::BaseEventKind;
using base::GateState;

constexpr int64_t kMs = 1'000'000;
constexpr int64_t kT0 = 1'700'000'000'000'000'000;

BaseEvent command(int64_t t_ms, int64_t age_ms, double lin, bool authenticated = true,
                  const std::string& source = "motion_controller") {
  BaseEvent e;
  e.kind = BaseEventKind::kCommand;
  e.time_ns = kT0 + t_ms * kMs;
  e.stamp_ns = e.time_ns - age_ms * kMs;
  e.authenticated = authenticated;
  e.key_id = authenticated ? 1 : 0;
  e.state = lin != 0.0 ? GateState::kDriving : GateState::kNoCommand;
  e.linear_mps = lin;
  e.source = source;
  return e;
}

BaseEvent frame(int64_t t_ms, double lin, bool estop = false) {
  BaseEvent e;
  e.kind = BaseEventKind::kFrame;
  e.time_ns = kT0 + t_ms * kMs;
  e.linear_mps = lin;
  e.estop_engaged = estop;
  return e;
}

BaseEvent estop(int64_t t_ms, bool engaged) {
  BaseEvent e;
  e.kind = BaseEventKind::kEstop;
  e.time_ns = kT0 + t_ms * kMs;
  e.estop_engaged = engaged;
  e.state = engaged ? GateState::kEmergencyStop : GateState::kNoCommand;
  return e;
}

// A robot driven by fresh authenticated commands, then stopping when they go stale.
std::vector<BaseEvent> clean_drive() {
  return {command(0, 5, 0.5), frame(33, 0.05),      frame(66, 0.1),  command(70, 5, 0.5),
          frame(100, 0.15),   frame(133, 0.2),      frame(400, 0.2), frame(433, 0.1),
          frame(466, 0.0),    command(500, 4, 0.0), frame(533, 0.0)};
}

TEST(NoUnsafeMotion, FreshAuthenticatedDrivingPasses) {
  // Given a log where the robot sped up only under fresh authenticated commands
  const auto events = clean_drive();
  // When checked
  const CheckResult r = check_no_unsafe_motion(events, CheckParams{});
  // Then it passes and counts what it saw
  EXPECT_TRUE(r.passed) << r.detail;
  EXPECT_EQ(r.violations, 0u);
  EXPECT_NE(r.detail.find("3 commands executed (2 moving"), std::string::npos) << r.detail;
}

TEST(NoUnsafeMotion, BaseMovingOnAStaleCommandIsCaught) {
  // Given the base let through a command 450 ms old (timeout 300 ms)
  auto events = clean_drive();
  events.push_back(command(600, 450, 0.4));
  // When checked
  const CheckResult r = check_no_unsafe_motion(events, CheckParams{});
  // Then it fails naming the command's age
  EXPECT_FALSE(r.passed);
  EXPECT_EQ(r.violations, 1u);
  EXPECT_NE(r.detail.find("aged 450 ms"), std::string::npos) << r.detail;
}

TEST(NoUnsafeMotion, RobotSpeedingUpAfterTheCommandExpiredIsCaught) {
  // Given the robot gains speed 500 ms after the last fresh command (nothing in force)
  auto events = clean_drive();
  events.push_back(frame(1100, 0.1));
  // When checked
  const CheckResult r = check_no_unsafe_motion(events, CheckParams{});
  // Then it fails
  EXPECT_FALSE(r.passed);
  EXPECT_NE(r.detail.find("sped up"), std::string::npos) << r.detail;
}

TEST(NoUnsafeMotion, UnauthenticatedOrRogueCommandsAreCaught) {
  // Given the base took an unverified command and one from the rogue
  auto events = clean_drive();
  events.push_back(command(700, 5, 0.3, false));
  events.push_back(command(800, 5, 0.0, true, "chaos-rogue"));
  // When checked with a keyed deployment
  const CheckResult r = check_no_unsafe_motion(events, CheckParams{});
  // Then both are violations
  EXPECT_FALSE(r.passed);
  EXPECT_EQ(r.violations, 2u);
  // And keyless (a loopback test deployment), the unverified one is allowed
  CheckParams keyless;
  keyless.keyed = false;
  std::vector<BaseEvent> unsigned_only = clean_drive();
  unsigned_only.push_back(command(700, 5, 0.3, false));
  EXPECT_TRUE(check_no_unsafe_motion(unsigned_only, keyless).passed);
}

TEST(EstopHeld, StandingStillWhileHeldPasses) {
  // Given a stop held from 1000 ms to 3000 ms; the robot brakes within the grace + braking
  std::vector<BaseEvent> events = {
      frame(900, 0.5),        estop(1000, true),      frame(1100, 0.3, true),
      command(1200, 5, 0.0),  frame(1600, 0.2, true), frame(2000, 0.0, true),
      frame(2900, 0.0, true), estop(3100, false),     frame(3500, 0.4)};
  Timeline timeline;
  timeline.estop.push_back({kT0 + 1000 * kMs, kT0 + 3000 * kMs});
  // When checked
  const CheckResult r = check_estop_held(events, timeline, CheckParams{});
  // Then it passes (frames before grace + braking are not judged; after the release they are
  // not either)
  EXPECT_TRUE(r.passed) << r.detail;
  EXPECT_TRUE(r.applicable);
}

TEST(EstopHeld, MotionWhileHeldIsCaught) {
  // Given the robot moves 1.5 s into a held stop and the base let a command through
  std::vector<BaseEvent> events = {estop(1000, true), frame(2500, 0.2, true),
                                   command(2600, 5, 0.3)};
  Timeline timeline;
  timeline.estop.push_back({kT0 + 1000 * kMs, kT0 + 3000 * kMs});
  // When checked
  const CheckResult r = check_estop_held(events, timeline, CheckParams{});
  // Then both are violations
  EXPECT_FALSE(r.passed);
  EXPECT_EQ(r.violations, 2u);
}

TEST(EstopHeld, NoStopIsNotApplicable) {
  const CheckResult r = check_estop_held(clean_drive(), Timeline{}, CheckParams{});
  EXPECT_TRUE(r.passed);
  EXPECT_FALSE(r.applicable);
}

TEST(Losses, GapsRestartsAndDuplicatesAreCounted) {
  // Given seq 0..4 with 2 missing, a duplicate of 4, then a restarted publisher 0..2 missing 1
  std::vector<SeqSample> s = {{0, 10}, {1, 20}, {3, 40}, {4, 50}, {4, 51}, {0, 100}, {2, 120}};
  // When counted with nothing excused
  const TopicLoss loss = count_losses("t", s, {});
  // Then
  EXPECT_EQ(loss.publisher_runs, 2u);
  EXPECT_EQ(loss.published, 8u);  // 0..4 and 0..2
  EXPECT_EQ(loss.recorded, 6u);
  EXPECT_EQ(loss.duplicates, 1u);
  EXPECT_EQ(loss.lost, 2u);
  EXPECT_FALSE(check_none_lost(std::vector<TopicLoss>{loss}).passed);
  // And when the second gap falls in an excused interval, only the first counts as lost
  const std::vector<Interval> cut = {{105, 115}};
  const TopicLoss excused = count_losses("t", s, cut);
  EXPECT_EQ(excused.lost, 1u);
  EXPECT_EQ(excused.lost_link_down, 1u);
}

TEST(Losses, CompleteStreamPasses) {
  std::vector<SeqSample> s = {{5, 1}, {6, 2}, {7, 3}};
  const TopicLoss loss = count_losses("t", s, {});
  EXPECT_EQ(loss.published, 3u);
  EXPECT_EQ(loss.recorded, 3u);
  EXPECT_TRUE(check_none_lost(std::vector<TopicLoss>{loss}).passed);
}

namespace {
constexpr int64_t kSec = 1'000'000'000;

// An instance started at 0 and sampled every 5 s from 10 s to end_s, VmRSS kb_at(t in s).
template <typename F>
MemorySpan sampled(const std::string& process, int pid, int end_s, F kb_at) {
  MemorySpan m;
  m.process = process, m.pid = pid, m.started_ns = 0;
  for (int t = 10; t <= end_s; t += 5) m.samples.push_back({t * kSec, kb_at(t)});
  m.first_ns = m.samples.front().t_ns, m.first_kb = m.samples.front().kb;
  m.last_ns = m.samples.back().t_ns, m.last_kb = m.samples.back().kb;
  return m;
}
}  // namespace

TEST(Memory, AWarmUpThatLevelsOffPassesASteadyGrowthFails) {
  // Given a detector whose working set forms in its first minute (60 % above its first
  // sample) and then stays flat, and a tracker that grows by 20 kB every 5 s for 10 minutes
  const std::vector<MemorySpan> spans = {
      sampled("ball_detector", 1, 600, [](int t) { return t < 60 ? 60'000L : 100'000L; }),
      sampled("tracker", 2, 600, [](int t) { return 10'000L + 20L * (t / 5); })};
  // When judged against 5 % after a 120 s settle, over at least 300 s
  const MemoryRule rule{120 * kSec, 60 * kSec, 300 * kSec, 5.0};
  const CheckResult r = check_memory(spans, rule);
  // Then the warm-up passes although its start -> end growth is 66 %, and the tracker fails
  EXPECT_GT(spans[0].growth_percent(), 60.0);
  const SettledGrowth detector = settled_growth(spans[0], rule);
  ASSERT_TRUE(detector.available);
  EXPECT_DOUBLE_EQ(detector.percent(), 0.0);
  EXPECT_FALSE(r.passed);
  EXPECT_EQ(r.violations, 1u);
  EXPECT_NE(r.detail.find("tracker (pid 2)"), std::string::npos) << r.detail;
  EXPECT_EQ(r.detail.find("ball_detector (pid 1)"), std::string::npos) << r.detail;
  // And the detail still names the start -> end growth beside the judged figure
  EXPECT_NE(r.detail.find("start -> end"), std::string::npos) << r.detail;
}

TEST(Memory, ASpikeInTheLastSampleIsNotAGrowth) {
  // Given a flat simulator whose very last sample caught a transient 12 % spike
  std::vector<MemorySpan> spans = {sampled("simulator", 1, 900, [](int) { return 75'000L; })};
  spans[0].samples.back().kb = spans[0].last_kb = 84'000;
  // Then its start -> end figure shows the spike, the judged (lowest of a window) one does not
  const MemoryRule rule{120 * kSec, 60 * kSec, 300 * kSec, 5.0};
  EXPECT_GT(spans[0].growth_percent(), 10.0);
  EXPECT_DOUBLE_EQ(settled_growth(spans[0], rule).percent(), 0.0);
  EXPECT_TRUE(check_memory(spans, rule).passed);
}

TEST(Memory, WorkThatComesAndGoesIsNotAGrowth) {
  // Given a simulator whose memory alternates between two levels every 20 s (its scenario loop)
  const std::vector<MemorySpan> spans = {
      sampled("simulator", 1, 900, [](int t) { return (t / 20) % 2 ? 83'000L : 76'500L; })};
  // Then whichever phase the windows catch, the judged growth is nil
  const MemoryRule rule{120 * kSec, 60 * kSec, 300 * kSec, 5.0};
  EXPECT_DOUBLE_EQ(settled_growth(spans[0], rule).percent(), 0.0);
  EXPECT_TRUE(check_memory(spans, rule).passed);
}

TEST(Memory, OnlyInstancesSettledLongEnoughAreJudged) {
  // Given one instance that doubled within 5 minutes of life, and one killed after a minute
  const std::vector<MemorySpan> spans = {
      sampled("tracker", 1, 300, [](int t) { return 10'000L + 100L * t; }),
      sampled("motion_controller", 2, 60, [](int t) { return 10'000L + 100L * t; })};
  // When at least 300 s after the 120 s settle are needed
  const MemoryRule rule{120 * kSec, 60 * kSec, 300 * kSec, 5.0};
  const CheckResult r = check_memory(spans, rule);
  // Then neither is judged: the check passes as not applicable, and says why
  EXPECT_TRUE(r.passed);
  EXPECT_FALSE(r.applicable);
  EXPECT_FALSE(settled_growth(spans[1], rule).available);
  EXPECT_NE(r.detail.find("no process instance settled"), std::string::npos) << r.detail;
}

TEST(Cdr, LeadingSeqInEitherByteOrder) {
  // Given the same seq encoded little- and big-endian after the encapsulation header
  const std::vector<uint8_t> le = {0, 1, 0, 0, 0x2a, 1, 0, 0, 0, 0, 0, 0};
  const std::vector<uint8_t> be = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0x2a};
  // Then both read 0x12a
  EXPECT_EQ(cdr_leading_u64(le).value(), 0x12au);
  EXPECT_EQ(cdr_leading_u64(be).value(), 0x12au);
  // And short or parameter-list samples are errors
  EXPECT_FALSE(cdr_leading_u64(std::vector<uint8_t>(6, 0)));
  const std::vector<uint8_t> pl = {0, 3, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0};
  EXPECT_FALSE(cdr_leading_u64(pl));
}

TEST(Plan, SeededOrderedAndComplete) {
  // Given a 10-minute plan
  PlanParams p;
  p.span_ns = 600 * 1'000'000'000LL;
  // When made twice with one seed and once with another
  const auto a = plan_faults(p, 7), b = plan_faults(p, 7), c = plan_faults(p, 8);
  // Then the same seed gives the same plan, another seed another
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].at_ns, b[i].at_ns);
    EXPECT_EQ(a[i].kind, b[i].kind);
  }
  bool differs = a.size() != c.size();
  for (size_t i = 0; !differs && i < a.size(); ++i) differs = a[i].at_ns != c[i].at_ns;
  EXPECT_TRUE(differs);
  // And faults never overlap, and every kind appears
  std::set<FaultKind> kinds;
  for (size_t i = 0; i < a.size(); ++i) {
    kinds.insert(a[i].kind);
    if (i > 0) {
      EXPECT_GE(a[i].at_ns, a[i - 1].at_ns + a[i - 1].duration_ns + p.min_gap_ns);
    }
    EXPECT_LT(a[i].at_ns, p.span_ns);
  }
  EXPECT_EQ(kinds.size(), 6u);
  // And without namespaces there is no link fault
  p.link = false;
  for (const auto& f : plan_faults(p, 7)) EXPECT_NE(f.kind, FaultKind::kCutLink);
}

TEST(Plan, FirstRoundHasEveryKindOnceAndStartsThePlan) {
  // Given a 10-minute plan, which repeats kinds after its first round
  PlanParams p;
  p.span_ns = 600 * 1'000'000'000LL;
  const auto plan = plan_faults(p, 7);
  // When its first round is taken
  const auto round = first_round(plan);
  // Then it is the plan's first six faults, one of each kind
  ASSERT_EQ(round.size(), 6u);
  std::set<FaultKind> kinds;
  for (size_t i = 0; i < round.size(); ++i) {
    EXPECT_EQ(round[i].at_ns, plan[i].at_ns);
    kinds.insert(round[i].kind);
  }
  EXPECT_EQ(kinds.size(), 6u);
  // And without namespaces it is five, none of them the link
  p.link = false;
  const auto no_link = first_round(plan_faults(p, 7));
  EXPECT_EQ(no_link.size(), 5u);
  for (const auto& f : no_link) EXPECT_NE(f.kind, FaultKind::kCutLink);
}

}  // namespace
}  // namespace stereoball::bench_chaos
