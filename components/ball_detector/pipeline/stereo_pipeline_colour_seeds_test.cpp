// StereoPipeline with and without colour-region seeds on randomised scenes of the shipped
// ranges whose ball the votes miss, rendered by the simulator: rand606_11, a white-and-purple
// striped 8.8 cm ball on grey tiles ("dark" in the categories; its white half nearly the tiles'
// grey); rand4242_10, lilac-and-olive stripes on grey carpet (the lilac rim as bright as the
// carpet's flecks), with and without the seeds' brightness-free search.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "ball_detector/pipeline/stereo_pipeline.hpp"
#include "simulator/core/ball_scene.hpp"
#include "simulator/core/randomize.hpp"
#include "simulator/core/simulator.hpp"

namespace sb = stereoball;
using sb::ball_detector::BallDetectorParams;
using sb::ball_detector::DetectionStatus;
using sb::ball_detector::StereoPipeline;

namespace {

// Frames (every stride-th of the first 40) on which the pipeline, whole-frame search each time
// (no prior), finds the ball within one radius of the truth.
int frames_found(const sb::simulator::RandomScene& scene, BallDetectorParams params, int& visible,
                 int stride = 5) {
  const auto sim_params = sb::simulator::default_sim_params();
  sb::simulator::Simulator sim(sim_params, scene.scenario);
  params.ball_diameter_m = scene.ball_diameter_m;
  StereoPipeline pipeline(params);
  EXPECT_TRUE(pipeline.set_calibration(sim.calibration()).ok());
  const double radius_m = 0.5 * scene.ball_diameter_m;
  int found = 0;
  visible = 0;
  const std::int64_t period = sim.frame_period_ns();
  for (int i = 0; i < 40; ++i) {
    const auto f = sim.step(std::nullopt, i * period);
    if (i % stride != 0 || !f.truth.ball_fully_visible_left || !f.truth.ball_fully_visible_right)
      continue;
    ++visible;
    const auto det = pipeline.step(f.left, f.right, false);
    const cv::Vec3d truth(f.truth.ball_camera_m.x, f.truth.ball_camera_m.y,
                          f.truth.ball_camera_m.z);
    if (det.status == DetectionStatus::kFound && cv::norm(det.position_m - truth) < radius_m)
      ++found;
  }
  return found;
}

}  // namespace

TEST(StereoPipelineColourSeeds,
     GivenAStripedBallWhoseLightHalfIsTheFloorsGrey_ThenOnlyColourSeedsFindIt) {
  const auto scene = sb::simulator::draw_scene(sb::simulator::RandomizeRanges{}, 606, 11);
  // The premise: the shipped ranges still draw this scene (else pick another such scene)
  ASSERT_EQ(scene.labels.pattern, "stripes");
  ASSERT_EQ(scene.labels.floor, "tiles/dark");
  ASSERT_LT(scene.ball_diameter_m, 0.1);
  int visible_with = 0, visible_without = 0;
  BallDetectorParams without_seeds;
  without_seeds.colour_seeds.enabled = false;
  const int with = frames_found(scene, BallDetectorParams{}, visible_with);
  const int without = frames_found(scene, without_seeds, visible_without);
  ASSERT_EQ(visible_with, visible_without);  // the same frames: nothing drives the robot
  ASSERT_GE(visible_with, 6);
  // Then with the seeds a whole-frame search alone finds the ball in at least half the frames
  // (measured: 4 of 7; in the benchmark the tracker's prior then keeps it), without them in
  // hardly any
  EXPECT_GE(2 * with, visible_with);
  EXPECT_LE(without, 1);
}

TEST(StereoPipelineColourSeeds,
     GivenALilacRimAsBrightAsTheGreyCarpet_ThenTheBrightnessFreeSearchPairsIt) {
  const auto scene = sb::simulator::draw_scene(sb::simulator::RandomizeRanges{}, 4242, 10);
  // The premise: the shipped ranges still draw this scene (else pick another such scene)
  ASSERT_EQ(scene.labels.pattern, "stripes");
  ASSERT_EQ(scene.labels.floor, "carpet/dark");
  int visible_with = 0, visible_without = 0;
  BallDetectorParams without_it;
  without_it.colour_seeds.chroma_outlines = false;
  const int with = frames_found(scene, BallDetectorParams{}, visible_with, 1);
  const int without = frames_found(scene, without_it, visible_without, 1);
  ASSERT_EQ(visible_with, visible_without);
  ASSERT_GE(visible_with, 30);
  std::printf("found in %d of %d frames with the brightness-free search, %d without\n", with,
              visible_with, without);
  // Then it pairs the ball in clearly more frames (measured: 29 of 40 against 19 of 40)
  EXPECT_GE(with, without + 6);
}
