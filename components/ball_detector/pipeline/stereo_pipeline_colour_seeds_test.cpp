// StereoPipeline with and without colour-region seeds on randomised scenes of the shipped
// ranges whose ball the votes miss, rendered by the simulator: rand606_11, a white-and-purple
// striped 8.8 cm ball on grey tiles ("dark" in the categories; its white half nearly the tiles'
// grey); rand4242_10, lilac-and-olive stripes on grey carpet (the lilac rim as bright as the
// carpet's flecks), with and without the brightness-free search (from the colour seeds, and from
// a prior's expected outline).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>

#include "ball_detector/pipeline/stereo_pipeline.hpp"
#include "simulator/core/ball_scene.hpp"
#include "simulator/core/randomize.hpp"
#include "simulator/core/simulator.hpp"

namespace sb = stereoball;
using sb::ball_detector::BallDetectorParams;
using sb::ball_detector::DetectionStatus;
using sb::ball_detector::StereoPipeline;

namespace {

struct Found {
  int found = 0;            // the pair within one ball radius of the truth
  int visible = 0;          // frames judged: the whole ball in view in both eyes
  int brightness_free = 0;  // found pairs the brightness-free search gave
};

// Frames (every stride-th of the first 40) on which the pipeline finds the ball: a whole-frame
// search each time, or, with prior_at_truth, first near a prior at the true position (as a
// track following the ball gives it).
Found frames_found(const sb::simulator::RandomScene& scene, BallDetectorParams params,
                   int stride = 5, bool prior_at_truth = false) {
  const auto sim_params = sb::simulator::default_sim_params();
  sb::simulator::Simulator sim(sim_params, scene.scenario);
  params.ball_diameter_m = scene.ball_diameter_m;
  StereoPipeline pipeline(params);
  EXPECT_TRUE(pipeline.set_calibration(sim.calibration()).ok());
  const double radius_m = 0.5 * scene.ball_diameter_m;
  Found out;
  const std::int64_t period = sim.frame_period_ns();
  for (int i = 0; i < 40; ++i) {
    const auto f = sim.step(std::nullopt, i * period);
    if (i % stride != 0 || !f.truth.ball_fully_visible_left || !f.truth.ball_fully_visible_right)
      continue;
    ++out.visible;
    const cv::Vec3d truth(f.truth.ball_camera_m.x, f.truth.ball_camera_m.y,
                          f.truth.ball_camera_m.z);
    std::optional<sb::ball_detector::PositionPrior> prior;
    if (prior_at_truth) prior = sb::ball_detector::PositionPrior{truth, 0.3};
    const auto det = pipeline.step(f.left, f.right, false, prior, i * period);
    if (det.status != DetectionStatus::kFound || cv::norm(det.position_m - truth) >= radius_m)
      continue;
    ++out.found;
    out.brightness_free += det.search == sb::ball_detector::SearchPath::kBrightnessFree;
  }
  return out;
}

}  // namespace

TEST(StereoPipelineColourSeeds,
     GivenAStripedBallWhoseLightHalfIsTheFloorsGrey_ThenOnlyColourSeedsFindIt) {
  const auto scene = sb::simulator::draw_scene(sb::simulator::RandomizeRanges{}, 606, 11);
  // The premise: the shipped ranges still draw this scene (else pick another such scene)
  ASSERT_EQ(scene.labels.pattern, "stripes");
  ASSERT_EQ(scene.labels.floor, "tiles/dark");
  ASSERT_LT(scene.ball_diameter_m, 0.1);
  BallDetectorParams without_seeds;
  without_seeds.colour_seeds.enabled = false;
  const Found f_with = frames_found(scene, BallDetectorParams{});
  const Found f_without = frames_found(scene, without_seeds);
  ASSERT_EQ(f_with.visible, f_without.visible);  // the same frames: nothing drives the robot
  ASSERT_GE(f_with.visible, 6);
  const int with = f_with.found, without = f_without.found, visible_with = f_with.visible;
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
  BallDetectorParams without_it;
  without_it.colour_seeds.chroma_outlines = false;
  const Found with = frames_found(scene, BallDetectorParams{}, 1);
  const Found without = frames_found(scene, without_it, 1);
  ASSERT_EQ(with.visible, without.visible);
  ASSERT_GE(with.visible, 30);
  std::printf("whole frame: found in %d of %d frames with the brightness-free search, %d without\n",
              with.found, with.visible, without.found);
  // Then it pairs the ball in clearly more frames (measured: 29 of 40 against 19 of 40)
  EXPECT_GE(with.found, without.found + 6);
  EXPECT_GE(with.brightness_free, 6);
}

TEST(StereoPipelineColourSeeds,
     GivenALilacRimAsBrightAsTheGreyCarpetAndAPriorThere_ThenItsExpectedOutlineIsSearchedToo) {
  const auto scene = sb::simulator::draw_scene(sb::simulator::RandomizeRanges{}, 4242, 10);
  ASSERT_EQ(scene.labels.floor, "carpet/dark");
  // Given a prior at the ball, as the tracker gives while following it, and no colour seeds (so
  // the whole-frame fallback cannot search without brightness: only the prior's path can)
  BallDetectorParams with_it;
  with_it.colour_seeds.enabled = false;
  BallDetectorParams without_it = with_it;
  without_it.colour_seeds.chroma_outlines = false;
  const Found with = frames_found(scene, with_it, 1, true);
  const Found without = frames_found(scene, without_it, 1, true);
  ASSERT_EQ(with.visible, without.visible);
  std::printf(
      "with a prior: found in %d of %d frames with the brightness-free search (%d by it), "
      "%d without\n",
      with.found, with.visible, with.brightness_free, without.found);
  // Then frames the prior's searches and the whole frame miss are found from the expected
  // outline without brightness (measured: 28 of 40, 6 of them by it, against 22 of 40)
  EXPECT_GE(with.found, without.found + 3);
  EXPECT_GE(with.brightness_free, 3);
}
