// Tests of the offline closed loop: event-driven controller after the control latency, its
// minimum rate, who drives the robot,
// configuration errors, and the nearest-rank percentile.

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <string>

#include "loop_config.hpp"
#include "run_each.hpp"
#include "sim_loop.hpp"

namespace stereoball::sim_loop {
namespace {

const std::string kConfigDir = std::string(SB_SOURCE_DIR) + "/config";

LoopConfig config_for(const std::string& scenario, Drive drive, double seconds) {
  auto c = load_loop_config(kConfigDir);
  EXPECT_TRUE(c.ok()) << c.error();
  LoopConfig config = c.value();
  auto s = load_scenario(scenario, kConfigDir + "/scenarios", false);
  EXPECT_TRUE(s.ok()) << s.error();
  config.scenario = s.value();
  config.drive = drive;
  config.seconds = seconds;
  return config;
}

TEST(SimLoop, GivenControllerDrive_ThenEachTrackIsAnsweredAfterTheControlLatency) {
  // Given the camera at 30 Hz, a 20 Hz minimum rate and 12 ms from exposure to controller
  LoopConfig config = config_for("no_ball", Drive::kController, 1.0);
  config.controller_rate_hz = 20.0;
  config.control_latency_ns = 12'000'000;
  auto run = run_all(config);
  ASSERT_TRUE(run.ok()) << run.error();
  ASSERT_EQ(run->frames.size(), 30u);
  // Then from the second frame on, the command in force is the answer to the previous frame's
  // track: issued 12 ms after that frame's exposure (tracks every 33 ms leave the minimum-rate
  // timer nothing to do)
  for (std::size_t i = 1; i < run->frames.size(); ++i) {
    const auto& f = run->frames[i];
    ASSERT_TRUE(f.command.has_value()) << i;
    const auto previous_ns =
        static_cast<std::int64_t>(std::llround(run->frames[i - 1].truth.sim_time_s * 1e9));
    EXPECT_EQ(f.command_stamp_ns, previous_ns + 12'000'000) << i;
  }
}

TEST(SimLoop, GivenControllerDriveAndNoTracksYet_ThenTheMinimumRateCommandsFirst) {
  // Given a latency longer than a frame period and a fast minimum rate (100 Hz)
  LoopConfig config = config_for("no_ball", Drive::kController, 0.2);
  config.controller_rate_hz = 100.0;
  config.control_latency_ns = 40'000'000;
  auto run = run_all(config);
  ASSERT_TRUE(run.ok()) << run.error();
  // Then before the first track arrives (40 ms) commands come every 10 ms from time 0, and no
  // command is ever more than 10 ms older than the frame
  for (const auto& f : run->frames) {
    ASSERT_TRUE(f.command.has_value());
    const auto frame_ns = static_cast<std::int64_t>(std::llround(f.truth.sim_time_s * 1e9));
    EXPECT_LE(f.command_stamp_ns, frame_ns);
    EXPECT_GT(f.command_stamp_ns, frame_ns - 10'000'001) << frame_ns;
    if (frame_ns < 40'000'000) {
      EXPECT_EQ(f.command_stamp_ns % 10'000'000, 0) << frame_ns;
    }
  }
}

TEST(SimLoop, GivenNoBallAndControllerDrive_ThenTheRobotStaysStill) {
  // Given no ball: the tracker never follows, so the controller commands nothing
  auto run = run_all(config_for("no_ball", Drive::kController, 1.0));
  ASSERT_TRUE(run.ok()) << run.error();
  // Then the robot has not moved or turned (the scenario's turning script is not used)
  const auto& last = run->frames.back().truth.robot;
  EXPECT_NEAR(last.yaw_rad, 0.0, 1e-9);
  EXPECT_NEAR(last.x_m, 0.0, 1e-9);
  EXPECT_FALSE(run->frames.back().truth.ball_present);
}

TEST(SimLoop, GivenScriptDrive_ThenTheScenarioScriptTurnsTheRobot) {
  // Given the no_ball script (turn left at 0.3 rad/s from t = 0)
  auto run = run_all(config_for("no_ball", Drive::kScript, 1.0));
  ASSERT_TRUE(run.ok()) << run.error();
  // Then the robot has turned left, and no controller command was issued
  EXPECT_GT(run->frames.back().truth.robot.yaw_rad, 0.1);
  EXPECT_FALSE(run->frames.back().command.has_value());
}

TEST(SimLoop, GivenBadRateOrLength_ThenCreateNamesTheProblem) {
  // Given a zero controller rate, Then the error names the rate
  LoopConfig config = config_for("no_ball", Drive::kController, 1.0);
  config.controller_rate_hz = 0.0;
  auto loop = SimLoop::create(config);
  ASSERT_FALSE(loop.ok());
  EXPECT_NE(loop.error().find("controller rate"), std::string::npos) << loop.error();
  // Given an invalid controller parameter, Then the error names the field
  config.controller_rate_hz = 20.0;
  config.controller.max_linear_mps = -1.0;
  loop = SimLoop::create(config);
  ASSERT_FALSE(loop.ok());
  EXPECT_NE(loop.error().find("max_linear_mps"), std::string::npos) << loop.error();
}

TEST(SimLoop, GivenFollowingTrack_ThenTheDetectorPriorInputCarriesItsPositionAndVelocity) {
  // Given a following track with a position and a velocity
  tracker::Track t;
  t.state = tracker::TrackState::kFollowing;
  t.position_valid = true;
  t.position_m = {0.1, 0.2, 1.5};
  t.velocity_mps = {0.3, 0.0, -0.4};
  // When converted for the detector (as the node converts ball/track)
  const auto b = to_tracked_ball(t, 123);
  // Then it is following, valid, stamped with the frame, and carries position and velocity
  EXPECT_TRUE(b.following);
  EXPECT_TRUE(b.position_valid);
  EXPECT_EQ(b.capture_stamp_ns, 123);
  EXPECT_DOUBLE_EQ(b.position_m[2], 1.5);
  EXPECT_DOUBLE_EQ(b.velocity_mps[0], 0.3);
  // And a searching track is not following (no prior from it)
  t.state = tracker::TrackState::kSearching;
  EXPECT_FALSE(to_tracked_ball(t, 123).following);
}

TEST(LoopConfig, GivenUnknownScenario_ThenErrorNamesIt) {
  auto s = load_scenario("no_such_scenario", kConfigDir + "/scenarios", false);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().find("no_such_scenario"), std::string::npos) << s.error();
}

TEST(LoopConfig, GivenPlain_ThenOneColourBallAndPlainRoom) {
  auto s = load_scenario("ball_still", kConfigDir + "/scenarios", true);
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_TRUE(s->room.plain);
  ASSERT_TRUE(s->ball.has_value());
  EXPECT_EQ(s->ball->color_b.r, s->ball->color_a.r);
  EXPECT_EQ(s->ball->color_b.g, s->ball->color_a.g);
  EXPECT_EQ(s->ball->color_b.b, s->ball->color_a.b);
}

TEST(Percentile, GivenTenValues_ThenNearestRankOfSortedCopy) {
  // Given ten values in any order
  const std::vector<double> v = {10, 1, 9, 2, 8, 3, 7, 4, 6, 5};
  // Then the median is the 5th smallest, p95 the 10th, and an empty list gives 0
  EXPECT_EQ(percentile(v, 0.5), 5.0);
  EXPECT_EQ(percentile(v, 0.95), 10.0);
  EXPECT_EQ(percentile({}, 0.5), 0.0);
}

}  // namespace
}  // namespace stereoball::sim_loop

// Given 40 runs writing their own slot, then with 1, 3 or more jobs than runs every slot holds
// its own index; given failures at 7 and 21, then one job runs nothing after 7 and the answer
// is 7's error, and 4 jobs also answer with 7's (every run claimed before it has run) and start
// few runs after it.
TEST(RunEach, GivenJobsThenEveryRunOnceAndTheFirstFailureInOrderAnswers) {
  namespace sl = stereoball::sim_loop;
  for (const int jobs : {1, 3, 64}) {
    std::vector<int> slot(40, -1);
    const auto status = sl::run_each(slot.size(), jobs, [&](std::size_t i) -> stereoball::Status {
      slot[i] = static_cast<int>(i);
      return {};
    });
    ASSERT_TRUE(status.ok());
    for (std::size_t i = 0; i < slot.size(); ++i) EXPECT_EQ(slot[i], static_cast<int>(i)) << jobs;
  }
  for (const int jobs : {1, 4}) {
    std::atomic<int> ran{0}, ran_after{0};
    const auto status = sl::run_each(40, jobs, [&](std::size_t i) -> stereoball::Status {
      ++ran;
      if (i > 7) ++ran_after;
      if (i == 7 || i == 21) return stereoball::Error{"run " + std::to_string(i) + " failed"};
      return {};
    });
    ASSERT_FALSE(status.ok());
    EXPECT_EQ(status.error(), "run 7 failed") << jobs;
    if (jobs == 1) {
      EXPECT_EQ(ran_after.load(), 0);
    }
    EXPECT_LT(ran.load(), 40) << jobs;
  }
  EXPECT_TRUE(sl::run_each(0, 4, [](std::size_t) -> stereoball::Status {
                return stereoball::Error{"never called"};
              }).ok());
}
