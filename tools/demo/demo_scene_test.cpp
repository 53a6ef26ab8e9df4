// The demo's leave scene keeps showing the paper's predictive search: ball_kicked_past_right
// run headless through the whole closed loop (simulator core, detector pipeline, tracker core,
// motion controller core) at simulated time, judged with the demo's leave events.

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <string>
#include <vector>

#include "closed_loop_run.hpp"
#include "loop_config.hpp"
#include "metrics.hpp"

namespace stereoball::demo {
namespace {

const std::string kConfigDir = std::string(SB_SOURCE_DIR) + "/config";

TEST(DemoScene, GivenBallKickedPastRight_ThenTrackLeavesSearchesRightAndReacquires) {
  // Given the shipped configuration and the scene, the motion controller driving, for 8 s of
  // simulated time (the kick is at 3 s; the shipped controller finds the ball ~2 s later)
  cv::setNumThreads(1);
  auto loaded = sim_loop::load_loop_config(kConfigDir);
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  sim_loop::LoopConfig config = loaded.value();
  auto scenario =
      sim_loop::load_scenario("ball_kicked_past_right", kConfigDir + "/scenarios", false);
  ASSERT_TRUE(scenario.ok()) << scenario.error();
  config.scenario = scenario.value();
  config.seconds = 8.0;
  // When the closed loop runs
  auto samples = bench_closed_loop::run_closed_loop(config);
  ASSERT_TRUE(samples.ok()) << samples.error();
  std::vector<TruthSample> truth;
  std::vector<TrackSample> tracks;
  for (const auto& s : samples.value()) {
    truth.push_back(s.truth);
    tracks.push_back(s.track);
  }
  const auto events = leave_events(truth, tracks);
  // Then the track follows the ball before the kick and loses it after it: at least one leave
  // event, the first after the kick
  ASSERT_GE(events.size(), 1u) << "the ball never left the view: the scene no longer shows the "
                                  "search (a faster controller? kick harder)";
  const LeaveEvent& e = events.front();
  EXPECT_GT(e.t_s, 3.0);
  // And the ball left by the right, the robot searched right, and the track follows again
  EXPECT_EQ(e.ball_side, Side::kRight);
  EXPECT_EQ(e.searched, Side::kRight) << side_name(e.searched);
  EXPECT_TRUE(e.reacquired) << "still searching at the end of the run, lost at " << e.t_s << " s";
  // And the robot was following the ball when the kick came (the leave is the kick's doing)
  int following_before_kick = 0, frames_before_kick = 0;
  for (const auto& s : samples.value()) {
    if (s.truth.t_s <= 2.5 || s.truth.t_s >= 3.0) continue;
    ++frames_before_kick;
    following_before_kick += s.track.state == TrackState::kFollowing ? 1 : 0;
  }
  EXPECT_GT(frames_before_kick, 0);
  EXPECT_EQ(following_before_kick, frames_before_kick);
}

}  // namespace
}  // namespace stereoball::demo
