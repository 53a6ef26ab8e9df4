// StereoPipeline with a runner that runs tasks at once (as the node's two threads do) against
// the same pipeline in turn: the work split for it (the left eye's rectification, its edges
// beside the colour blobs, its votes in shares) changes no detection, bit for bit.

#include <gtest/gtest.h>

#include <functional>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "ball_detector/pipeline/stereo_pipeline.hpp"
#include "simulator/core/simulator.hpp"
#include "simulator/io/scenario_file.hpp"

namespace sb = stereoball;
using sb::ball_detector::BallDetectorParams;
using sb::ball_detector::DetectionStatus;
using sb::ball_detector::StereoDetection;
using sb::ball_detector::StereoPipeline;

namespace {

// Every task but the first on a thread of its own, all at once; counts the calls with n > 1.
struct AtOnceRunner {
  int calls = 0;
  void operator()(int n, const std::function<void(int)>& task) {
    if (n > 1) ++calls;
    std::vector<std::thread> threads;
    for (int i = 1; i < n; ++i) threads.emplace_back([&task, i] { task(i); });
    if (n > 0) task(0);
    for (auto& t : threads) t.join();
  }
};

void expect_same_detection(const StereoDetection& a, const StereoDetection& b, int frame) {
  SCOPED_TRACE("frame " + std::to_string(frame));
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.reason, b.reason);
  EXPECT_EQ(a.search, b.search);
  EXPECT_EQ(a.left.x_px, b.left.x_px);
  EXPECT_EQ(a.left.y_px, b.left.y_px);
  EXPECT_EQ(a.left.radius_px, b.left.radius_px);
  EXPECT_EQ(a.left.score, b.left.score);
  EXPECT_EQ(a.right.x_px, b.right.x_px);
  EXPECT_EQ(a.right.radius_px, b.right.radius_px);
  EXPECT_EQ(a.position_m, b.position_m);
  EXPECT_EQ(a.candidates_left, b.candidates_left);
  EXPECT_EQ(a.candidates_right, b.candidates_right);
}

}  // namespace

TEST(StereoPipelineTasks, GivenTasksAtOnceThenTheDetectionsAreThoseInTurn) {
  // Given ball_leaves_left rendered with the robot still (found, leaving, lost: the whole-frame
  // and band searches of a lost ball), and two pipelines: one in turn, one whose runner runs
  // the tasks at once
  auto scenario = sb::simulator::load_scenario_by_name(
      "ball_leaves_left", std::string(SB_SOURCE_DIR) + "/config/scenarios");
  ASSERT_TRUE(scenario.ok()) << scenario.error();
  sb::simulator::Simulator sim(sb::simulator::default_sim_params(), *scenario);
  BallDetectorParams params;
  params.ball_diameter_m = 2.0 * scenario->ball->radius_m;
  StereoPipeline in_turn(params), at_once(params);
  ASSERT_TRUE(in_turn.set_calibration(sim.calibration()).ok());
  ASSERT_TRUE(at_once.set_calibration(sim.calibration()).ok());
  AtOnceRunner runner;
  at_once.set_task_runner(std::ref(runner), 2);
  const std::int64_t period = sim.frame_period_ns();
  int found = 0, lost = 0;
  for (int i = 0; i < 150; ++i) {
    const auto f = sim.step(std::nullopt, i * period);
    if (i % 3 != 0) continue;  // every third frame: the ball moves on between them
    // When both detect the frame
    const StereoDetection a = in_turn.step(f.left, f.right, false, std::nullopt, i * period);
    const StereoDetection b = at_once.step(f.left, f.right, false, std::nullopt, i * period);
    in_turn.finish_frame(f.left, false);
    at_once.finish_frame(f.left, false);
    // Then they are the same
    expect_same_detection(a, b, i);
    found += a.status == DetectionStatus::kFound;
    lost += a.status != DetectionStatus::kFound;
  }
  // And the frames held both answers, and the work was split for the runner
  EXPECT_GT(found, 5);
  EXPECT_GT(lost, 5);
  EXPECT_GT(runner.calls, 3 * lost) << "rectification, edges and votes of each lost frame";
}
