// StereoPipeline with and without balancing a pair's outline radii, on a randomised scene
// whose two fits disagree: rand7777_8 of the shipped ranges, a red-and-white panelled 9.7 cm
// ball on light planks 2-3 m away, rendered by the simulator. A panel boundary just inside one
// eye's rim pulls that eye's circle in, and half a pixel of disparity is 2 % of the depth there.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "ball_detector/pipeline/stereo_pipeline.hpp"
#include "simulator/core/ball_scene.hpp"
#include "simulator/core/randomize.hpp"
#include "simulator/core/simulator.hpp"

namespace sb = stereoball;
using sb::ball_detector::BallDetectorParams;
using sb::ball_detector::DetectionStatus;
using sb::ball_detector::StereoPipeline;

namespace {

// The 3D error of each of the first 60 frames' detections (metres; frames where either run
// finds nothing are left out by the caller), whole-frame search each time (no prior).
std::vector<double> errors_m(const sb::simulator::RandomScene& scene, bool balance) {
  const auto sim_params = sb::simulator::default_sim_params();
  sb::simulator::Simulator sim(sim_params, scene.scenario);
  BallDetectorParams params;
  params.ball_diameter_m = scene.ball_diameter_m;
  params.balance_radii = balance;
  StereoPipeline pipeline(params);
  EXPECT_TRUE(pipeline.set_calibration(sim.calibration()).ok());
  std::vector<double> out;
  const std::int64_t period = sim.frame_period_ns();
  for (int i = 0; i < 60; ++i) {
    const auto f = sim.step(std::nullopt, i * period);
    const auto det = pipeline.step(f.left, f.right, false);
    const cv::Vec3d truth(f.truth.ball_camera_m.x, f.truth.ball_camera_m.y,
                          f.truth.ball_camera_m.z);
    const bool judged = f.truth.ball_fully_visible_left && f.truth.ball_fully_visible_right &&
                        det.status == DetectionStatus::kFound;
    out.push_back(judged ? cv::norm(det.position_m - truth) : -1.0);
  }
  return out;
}

}  // namespace

TEST(StereoPipelineBalanceRadii, GivenASmallPanelledBallFarAway_ThenBalancedRadiiKeepItsCentre) {
  const auto scene = sb::simulator::draw_scene(sb::simulator::RandomizeRanges{}, 7777, 8);
  // The premise: the shipped ranges still draw this scene (else pick another such scene)
  ASSERT_EQ(scene.labels.pattern, "panels");
  ASSERT_EQ(scene.labels.floor, "planks/light");
  ASSERT_LT(scene.ball_diameter_m, 0.1);
  const auto with = errors_m(scene, true);
  const auto without = errors_m(scene, false);
  const double radius_m = 0.5 * scene.ball_diameter_m;
  int both = 0, off_with = 0, off_without = 0;
  std::vector<double> e_with, e_without;
  for (std::size_t i = 0; i < with.size(); ++i) {
    if (with[i] < 0.0 || without[i] < 0.0) continue;
    ++both;
    off_with += with[i] > radius_m;
    off_without += without[i] > radius_m;
    e_with.push_back(with[i]);
    e_without.push_back(without[i]);
  }
  ASSERT_GE(both, 30);
  std::sort(e_with.begin(), e_with.end());
  std::sort(e_without.begin(), e_without.end());
  const auto p90 = [](const std::vector<double>& e) { return e[e.size() * 9 / 10]; };
  std::printf("frames %d: off the ball %d -> %d, p90 error %.1f -> %.1f mm\n", both, off_without,
              off_with, 1e3 * p90(e_without), 1e3 * p90(e_with));
  // Then fewer detections fall off the ball, and the worst tenth of the errors shrinks
  EXPECT_LT(off_with, off_without);
  EXPECT_LT(p90(e_with), p90(e_without));
}
