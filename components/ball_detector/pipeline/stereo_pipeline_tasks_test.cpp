// StereoPipeline with a runner that runs tasks at once (as the node's two threads do) against
// the same pipeline in turn: the work split for it (the left eye's rectification, its edges
// beside the colour blobs, its votes in shares, the radius bands' votes beside the left peaks
// and their peaks beside the pairing) changes no detection, bit for bit.

#include <gtest/gtest.h>

#include <functional>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "ball_detector/pipeline/stereo_pipeline.hpp"
#include "ball_detector/pipeline/task_runners_test_support.hpp"
#include "simulator/core/simulator.hpp"
#include "simulator/io/scenario_file.hpp"

namespace sb = stereoball;
using sb::ball_detector::BallDetectorParams;
using sb::ball_detector::DetectionStatus;
using sb::ball_detector::StereoDetection;
using sb::ball_detector::StereoPipeline;

namespace {

using sb::ball_detector::testing::AtOnceRunner;
using sb::ball_detector::testing::InTurnRunner;

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

// Frames of a scenario with the robot still (ball_leaves_left: found, leaving, lost, i.e. the
// whole-frame and band searches of a lost ball), every `every`-th one, detected by a pipeline in
// turn and by one whose runner (declared to run 2 tasks at once) is runner, both coarse to fine
// by radius when by_radius; returns how many were found and lost.
template <typename Runner>
std::pair<int, int> expect_runner_detects_as_in_turn(Runner& runner, int frames,
                                                     const std::string& name = "ball_leaves_left",
                                                     int every = 3, bool by_radius = false) {
  auto scenario =
      sb::simulator::load_scenario_by_name(name, std::string(SB_SOURCE_DIR) + "/config/scenarios");
  EXPECT_TRUE(scenario.ok()) << scenario.error();
  if (!scenario.ok()) return {0, 0};
  sb::simulator::Simulator sim(sb::simulator::default_sim_params(), *scenario);
  BallDetectorParams params;
  params.ball_diameter_m = 2.0 * scenario->ball->radius_m;
  params.coarse_by_radius = by_radius;
  StereoPipeline in_turn(params), split(params);
  EXPECT_TRUE(in_turn.set_calibration(sim.calibration()).ok());
  EXPECT_TRUE(split.set_calibration(sim.calibration()).ok());
  split.set_task_runner(std::ref(runner), 2);
  const std::int64_t period = sim.frame_period_ns();
  int found = 0, lost = 0;
  for (int i = 0; i < frames; ++i) {
    const auto f = sim.step(std::nullopt, i * period);
    if (i % every != 0) continue;  // the ball moves on between the frames detected
    const StereoDetection a = in_turn.step(f.left, f.right, false, std::nullopt, i * period);
    const StereoDetection b = split.step(f.left, f.right, false, std::nullopt, i * period);
    in_turn.finish_frame(f.left, false);
    split.finish_frame(f.left, false);
    expect_same_detection(a, b, i);
    found += a.status == DetectionStatus::kFound;
    lost += a.status != DetectionStatus::kFound;
  }
  return {found, lost};
}

}  // namespace

TEST(StereoPipelineTasks, GivenTasksAtOnceThenTheDetectionsAreThoseInTurn) {
  // Given two pipelines: one in turn, one whose runner runs the tasks at once
  AtOnceRunner runner;
  // When both detect the frames, Then they are the same
  const auto [found, lost] = expect_runner_detects_as_in_turn(runner, 150);
  // And the frames held both answers, and the work was split for the runner
  EXPECT_GT(found, 5);
  EXPECT_GT(lost, 5);
  EXPECT_GT(runner.calls, 4 * lost)
      << "rectification, edges, votes, band votes beside the peaks, pairing beside the band "
         "peaks of each lost frame";
}

// Coarse to fine by radius (coarse_to_fine.by_radius): the lost frames' halved eye and bands
// split for the runner (by_radius_beside_bands) give the detections in turn as well.
TEST(StereoPipelineTasks, GivenTasksAtOnceByRadiusThenTheDetectionsAreThoseInTurn) {
  // Given two pipelines by radius: one in turn, one whose runner runs the tasks at once
  AtOnceRunner runner;
  // When both detect the frames, Then they are the same
  const auto [found, lost] =
      expect_runner_detects_as_in_turn(runner, 150, "ball_leaves_left", 3, true);
  // And the frames held both answers, and the work was split for the runner
  EXPECT_GT(found, 5);
  EXPECT_GT(lost, 5);
  EXPECT_GT(runner.calls, 4 * lost)
      << "rectification, edges beside the blobs, halved votes, full-width lines, band votes "
         "beside the halved eye's circles, pairing beside the band peaks of each lost frame";
}

// The same split run in turn on one thread (the order a busy helper leaves: the caller runs
// every task): the band votes before the left peaks, the band peaks after the pairing.
TEST(StereoPipelineTasks, GivenTheSplitRunInTurnThenTheDetectionsAreThoseInTurn) {
  // Given a pipeline told it has 2 threads whose runner runs the tasks one after the other
  InTurnRunner runner;
  // When it and a pipeline in turn detect the frames, Then they are the same
  const auto [found, lost] = expect_runner_detects_as_in_turn(runner, 150);
  EXPECT_GT(found, 5);
  EXPECT_GT(lost, 5);
  EXPECT_GT(runner.calls, 4 * lost);
}
