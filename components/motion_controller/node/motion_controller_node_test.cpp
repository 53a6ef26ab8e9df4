// Integration test: the real motion_controller process on a private domain,
// fed ball/track and cmd/estop; checks cmd/velocity.

#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <optional>
#include <thread>
#include <vector>

#include "common/dds/reader.hpp"
#include "common/dds/writer.hpp"
#include "common/node/node_runner.hpp"
#include "process.hpp"

namespace sb = stereoball;
using namespace std::chrono_literals;
using sb::testing::Process;

namespace {

struct Cmd {
  double linear_mps;
  double angular_radps;
  std::int64_t stamp_ns;  // when the node issued it (its own clock, the host's epoch)
  std::int64_t capture_stamp_ns;
  std::uint64_t seq = 0;  // the node's command counter
};

// Median gap between consecutive issue stamps, ms. Judged on the node's own stamps, not on
// when this test happened to take the samples, so a busy host delays delivery without failing
// the rate check; one late timer tick does not move the median.
double median_issue_gap_ms(const std::vector<Cmd>& cmds) {
  std::vector<double> gaps;
  for (std::size_t i = 1; i < cmds.size(); ++i) {
    gaps.push_back(static_cast<double>(cmds[i].stamp_ns - cmds[i - 1].stamp_ns) / 1e6);
  }
  if (gaps.empty()) return 0.0;
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
  return gaps[gaps.size() / 2];
}

stereoball_msg_BallTrack track(stereoball_msg_TrackState state, double bearing_rad,
                               double distance_m, stereoball_msg_Side side) {
  stereoball_msg_BallTrack t{};
  t.state = state;
  t.verdict = stereoball_msg_VERDICT_BLOCK_MATCH_ACCEPTED;
  t.reason = const_cast<char*>("test");
  t.position_valid = state != stereoball_msg_TRACK_IDLE;
  t.bearing_rad = bearing_rad;
  t.distance_m = distance_m;
  t.last_seen_side = side;
  return t;
}

class MotionControllerNodeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    partition_ = sb::testing::unique_partition();
    node_.emplace(
        Process::start({sb::testing::bin("motion_controller"), "--config",
                        sb::testing::source_path("config/motion_controller.yaml"), "--domain",
                        std::to_string(sb::testing::test_domain()), "--partition", partition_}));
    participant_.emplace(sb::dds::ParticipantOptions{sb::testing::test_domain(), partition_});
    tracks_.emplace(*participant_, sb::topics::kBallTrack);
    estop_.emplace(*participant_, sb::topics::kEmergencyStop);
    commands_.emplace(*participant_, sb::topics::kVelocityCommand);
    ASSERT_TRUE(tracks_->wait_for_readers(1, 10'000'000'000)) << node_->output();
    ASSERT_TRUE(commands_->wait_for_writers(1, 10'000'000'000)) << node_->output();
    // Discovery is not symmetric: our reader knowing the node's writer does not mean the writer
    // knows our reader yet, and a command written before then never reaches us. The node
    // commands at its minimum rate without tracks, so one received command proves the path.
    const auto end = std::chrono::steady_clock::now() + 10s;
    while (commands_->take().empty()) {
      ASSERT_LT(std::chrono::steady_clock::now(), end)
          << "no command from the node within 10 s" << node_->output();
      std::this_thread::sleep_for(5ms);
    }
  }

  // For duration, publishes t (if given) at 30 Hz and collects every command received.
  std::vector<Cmd> pump(const std::optional<stereoball_msg_BallTrack>& t,
                        std::chrono::milliseconds duration) {
    std::vector<Cmd> got;
    const auto end = std::chrono::steady_clock::now() + duration;
    while (std::chrono::steady_clock::now() < end) {
      if (t) {
        stereoball_msg_BallTrack s = *t;
        s.capture_stamp_ns = s.last_accepted_stamp_ns = sb::node::now_ns();
        s.frame_seq = ++seq_;
        tracks_->write(s);
      }
      collect(got);
      std::this_thread::sleep_for(33ms);
    }
    collect(got);
    return got;
  }

  void collect(std::vector<Cmd>& got) {
    for (auto& s : commands_->take()) {
      got.push_back({s->linear_mps, s->angular_radps, s->stamp_ns, s->capture_stamp_ns, s->seq});
    }
  }

  // Publishes t stamped capture_stamp_ns, then collects commands until one answers it (true)
  // or the deadline passes (false).
  bool send_and_wait_for_answer(stereoball_msg_BallTrack t, std::int64_t capture_stamp_ns,
                                std::vector<Cmd>& got, std::chrono::milliseconds deadline) {
    t.capture_stamp_ns = t.last_accepted_stamp_ns = capture_stamp_ns;
    t.frame_seq = ++seq_;
    tracks_->write(t);
    const auto end = std::chrono::steady_clock::now() + deadline;
    while (std::chrono::steady_clock::now() < end) {
      collect(got);
      for (const auto& c : got) {
        if (c.capture_stamp_ns == capture_stamp_ns) return true;
      }
      std::this_thread::sleep_for(2ms);
    }
    return false;
  }

  void send_estop(bool engaged) {
    stereoball_msg_EmergencyStop e{};
    e.stamp_ns = sb::node::now_ns();
    e.engaged = engaged;
    e.reason = const_cast<char*>("test");
    estop_->write(e);
  }

  std::string partition_;
  std::optional<Process> node_;
  std::optional<sb::dds::DomainParticipant> participant_;
  std::optional<sb::dds::DataWriter<stereoball_msg_BallTrack>> tracks_;
  std::optional<sb::dds::DataWriter<stereoball_msg_EmergencyStop>> estop_;
  std::optional<sb::dds::DataReader<stereoball_msg_VelocityCommand>> commands_;
  std::uint64_t seq_ = 0;
};

TEST_F(MotionControllerNodeTest, GivenNoInput_ThenZeroCommandsAtAbout20Hz) {
  pump(std::nullopt, 300ms);  // let the timer settle
  const auto cmds = pump(std::nullopt, 2000ms);
  ASSERT_GE(cmds.size(), 10u) << node_->output();
  // 20 Hz: the timer's period, whatever the host's load did to delivery
  EXPECT_NEAR(median_issue_gap_ms(cmds), 50.0, 10.0);
  EXPECT_LE(cmds.size(), 50u);
  for (const auto& c : cmds) {
    EXPECT_EQ(c.linear_mps, 0.0);
    EXPECT_EQ(c.angular_radps, 0.0);
  }
}

TEST_F(MotionControllerNodeTest, GivenBallToTheRightFar_ThenTurnsRightAndDrives) {
  const auto cmds =
      pump(track(stereoball_msg_TRACK_FOLLOWING, 0.2, 2.0, stereoball_msg_SIDE_RIGHT), 1500ms);
  ASSERT_FALSE(cmds.empty());
  EXPECT_LT(cmds.back().angular_radps, -0.1) << node_->output();
  EXPECT_GT(cmds.back().linear_mps, 0.1);
}

TEST_F(MotionControllerNodeTest, GivenTrackStops_ThenZeroWithinHalfASecond) {
  pump(track(stereoball_msg_TRACK_FOLLOWING, 0.0, 2.0, stereoball_msg_SIDE_RIGHT), 1500ms);
  const std::int64_t stopped_at_ns = sb::node::now_ns();
  const auto cmds = pump(std::nullopt, 1000ms);
  ASSERT_GT(cmds.size(), 10u);
  // Commands keep coming although the input stopped, and those issued 0.5 s after the last
  // track are zero (issue stamps: a busy host may deliver them late, not issue them late)
  EXPECT_GT(cmds.front().linear_mps, 0.0);
  for (const auto& c : cmds) {
    if (c.stamp_ns - stopped_at_ns > 500'000'000) {
      EXPECT_EQ(c.linear_mps, 0.0);
      EXPECT_EQ(c.angular_radps, 0.0);
    }
  }
  EXPECT_EQ(cmds.back().linear_mps, 0.0);
}

TEST_F(MotionControllerNodeTest, GivenEmergencyStop_ThenZeroLatchedUntilCleared) {
  const auto following = track(stereoball_msg_TRACK_FOLLOWING, -0.2, 2.0, stereoball_msg_SIDE_LEFT);
  ASSERT_GT(pump(following, 1000ms).back().linear_mps, 0.1);
  send_estop(true);
  const auto during = pump(following, 1000ms);
  ASSERT_FALSE(during.empty());
  EXPECT_EQ(during.back().linear_mps, 0.0);
  EXPECT_EQ(during.back().angular_radps, 0.0);
  // Latched: all commands of the last half second are zero although tracks continue
  for (std::size_t i = during.size() / 2; i < during.size(); ++i) {
    EXPECT_EQ(during[i].linear_mps, 0.0);
  }
  send_estop(false);
  const auto after = pump(following, 1000ms);
  EXPECT_GT(after.back().linear_mps, 0.1);
  EXPECT_GT(after.back().angular_radps, 0.1);  // ball to the left: counter-clockwise
}

TEST_F(MotionControllerNodeTest, GivenEmergencyStopAndStaleInput_ThenZeroAtTheMinimumRateOnly) {
  // Given a followed ball, then the e-stop engaged and the tracks stopping, so the input goes
  // stale while the stop is held (the stop's mode, not STALE, is what the node commands)
  const auto following = track(stereoball_msg_TRACK_FOLLOWING, 0.0, 2.0, stereoball_msg_SIDE_LEFT);
  pump(following, 500ms);
  send_estop(true);
  pump(std::nullopt, 1000ms);
  // When the node is watched for 2 s more
  const auto cmds = pump(std::nullopt, 2000ms);
  ASSERT_GE(cmds.size(), 5u) << node_->output();
  // Then every command is zero, and the node issued them at its minimum rate (20 Hz), not at
  // the pace of its wake-ups: counted by the node's own command numbers and issue stamps, so a
  // busy host's late delivery does not count
  for (const auto& c : cmds) {
    EXPECT_EQ(c.linear_mps, 0.0);
    EXPECT_EQ(c.angular_radps, 0.0);
  }
  const double span_ms = static_cast<double>(cmds.back().stamp_ns - cmds.front().stamp_ns) / 1e6;
  const auto issued = static_cast<double>(cmds.back().seq - cmds.front().seq);
  EXPECT_LE(issued, span_ms / 40.0 + 3.0) << "issued " << issued << " in " << span_ms << " ms";
  EXPECT_GE(issued, span_ms / 100.0) << "issued " << issued << " in " << span_ms << " ms";
}

TEST_F(MotionControllerNodeTest, GivenSearchingAfterLeftExit_ThenRotatesLeftInPlace) {
  const auto cmds =
      pump(track(stereoball_msg_TRACK_SEARCHING, 0.0, 0.0, stereoball_msg_SIDE_LEFT), 1000ms);
  ASSERT_FALSE(cmds.empty());
  EXPECT_NEAR(cmds.back().angular_radps, 0.8, 1e-9);
  EXPECT_EQ(cmds.back().linear_mps, 0.0);
}

std::size_t answers_to(const std::vector<Cmd>& cmds, std::int64_t capture_stamp_ns) {
  return static_cast<std::size_t>(std::count_if(cmds.begin(), cmds.end(), [&](const Cmd& c) {
    return c.capture_stamp_ns == capture_stamp_ns;
  }));
}

TEST_F(MotionControllerNodeTest, GivenNewTracks_ThenEachAnsweredByExactlyOneCommand) {
  // Given a following track, sent 8 times with new capture stamps and once more repeated
  const auto t = track(stereoball_msg_TRACK_FOLLOWING, 0.1, 2.0, stereoball_msg_SIDE_RIGHT);
  std::vector<Cmd> got;
  std::vector<std::int64_t> stamps;
  for (int i = 0; i < 8; ++i) {
    stamps.push_back(sb::node::now_ns());
    // When each arrives, Then a command answers it (generous deadline: the host is shared)
    ASSERT_TRUE(send_and_wait_for_answer(t, stamps.back(), got, 5s)) << i << node_->output();
  }
  send_and_wait_for_answer(t, stamps.back(), got, 300ms);  // the last frame once more
  collect(got);
  // Then every track got exactly one command carrying its capture stamp unchanged, the
  // repeated one none more, and every other command comes from the timer (stamp 0)
  for (const auto stamp : stamps) EXPECT_EQ(answers_to(got, stamp), 1u) << stamp;
  for (const auto& c : got) {
    const bool known = c.capture_stamp_ns == 0 ||
                       std::find(stamps.begin(), stamps.end(), c.capture_stamp_ns) != stamps.end();
    EXPECT_TRUE(known) << c.capture_stamp_ns;
  }
}

TEST_F(MotionControllerNodeTest, GivenBadCaptureStamps_ThenNoCommandAndAClearLogLine) {
  const auto t = track(stereoball_msg_TRACK_FOLLOWING, 0.1, 2.0, stereoball_msg_SIDE_RIGHT);
  std::vector<Cmd> got;
  std::vector<std::int64_t> rejected;
  const std::pair<const char*, std::int64_t> cases[] = {
      {"going backwards", -1'000'000}, {"in the future", 10'000'000'000}, {"zero (never set)", 0}};
  for (const auto& [reason, offset_ns] : cases) {
    // Given a good track that was answered (the input is live: an earlier stream would
    // otherwise be a restart)
    const std::int64_t good = sb::node::now_ns();
    ASSERT_TRUE(send_and_wait_for_answer(t, good, got, 5s)) << node_->output();
    // When a track arrives stamped before it, 10 s in the future, or zero
    stereoball_msg_BallTrack bad = t;
    bad.capture_stamp_ns = bad.last_accepted_stamp_ns = offset_ns == 0 ? 0 : good + offset_ns;
    bad.frame_seq = ++seq_;
    if (offset_ns != 0) rejected.push_back(bad.capture_stamp_ns);
    tracks_->write(bad);
    // Then the node says what was wrong (generous deadline: the host is shared)
    EXPECT_TRUE(node_->wait_for_output(reason, 5s)) << reason << node_->output();
  }
  EXPECT_NE(node_->output().find("no command built on it"), std::string::npos);
  // And no command answered a rejected track (zero-stamped commands are the timer's)
  std::this_thread::sleep_for(100ms);
  collect(got);
  for (const auto stamp : rejected) EXPECT_EQ(answers_to(got, stamp), 0u) << stamp;
}

TEST_F(MotionControllerNodeTest, GivenSigterm_ThenExitsZero) {
  node_->signal(SIGTERM);
  EXPECT_EQ(node_->wait_for_exit(5s), 0) << node_->output();
}

TEST(MotionControllerNodeCli, GivenBadConfig_ThenOneClearLineAndNonZeroExit) {
  const std::string dir = sb::testing::temp_dir();
  std::ofstream(dir + "/bad.yaml") << "rate_hz: 20\n";
  const auto [code, out] =
      sb::testing::run({sb::testing::bin("motion_controller"), "--config", dir + "/bad.yaml"}, 10s);
  EXPECT_NE(code, 0);
  EXPECT_NE(out.find("bad.yaml"), std::string::npos) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
}

TEST(MotionControllerNodeCli, GivenHelp_ThenDescribesTopicsAndExitsZero) {
  const auto [code, out] = sb::testing::run({sb::testing::bin("motion_controller"), "--help"}, 10s);
  EXPECT_EQ(code, 0);
  EXPECT_NE(out.find("cmd/velocity"), std::string::npos) << out;
}

}  // namespace
