// The followed ball's appearance in the stereo pipeline: learnt from pairs found where the
// tracker expects the ball, it rejects a same-size ball of another colour at the same place,
// and is forgotten after a loss longer than its timeout.

#include <gtest/gtest.h>

#include "ball_detector/pipeline/stereo_pipeline.hpp"
#include "simulator/core/ball_scene.hpp"

namespace sb = stereoball;
using sb::ball_detector::DetectionStatus;
using sb::ball_detector::StereoPipeline;

namespace {

constexpr std::int64_t kFrameNs = 33'333'333;

struct RenderedScene {
  sb::simulator::SimFrame frame;
  sb::stereo::StereoCalibration calib;
};

// A one-colour ball of colour (r, g, b) 1.4 m ahead in a plain room.
RenderedScene render_ball(sb::simulator::Rgb colour) {
  sb::simulator::SimBallSetup setup;
  setup.ball_x_m = 1.4;
  setup.ball_y_m = 0.1;
  setup.clutter = false;
  setup.plain_room = true;
  auto scenario = sb::simulator::make_sim_scenario(setup);
  scenario.ball->color_a = scenario.ball->color_b = colour;
  sb::simulator::Simulator sim(sb::simulator::default_sim_params(), scenario);
  return {sim.step(std::nullopt, 0), sim.calibration()};
}

sb::ball_detector::PositionPrior prior_at(const sb::simulator::GroundTruth& t) {
  return {{t.ball_camera_m.x, t.ball_camera_m.y, t.ball_camera_m.z}, 0.3};
}

// The orange ball, then a blue one (both dark enough in red to stand out of the grey floor).
const sb::simulator::Rgb kOrange{230, 110, 20}, kBlue{30, 60, 200};

}  // namespace

TEST(StereoPipelineAppearance, LearntBallRejectsABallOfAnotherColourUntilForgotten) {
  const RenderedScene orange = render_ball(kOrange), blue = render_ball(kBlue);
  sb::ball_detector::BallDetectorParams params;
  params.appearance.forget_after_ns = 1'000'000'000;
  // Given a pipeline that follows the orange ball for a few frames (a prior at its position)
  StereoPipeline pipe(params);
  ASSERT_TRUE(pipe.set_calibration(orange.calib).ok());
  std::int64_t t = 0;
  for (int i = 0; i < 4; ++i, t += kFrameNs) {
    const auto d =
        pipe.step(orange.frame.left, orange.frame.right, false, prior_at(orange.frame.truth), t);
    ASSERT_EQ(d.status, DetectionStatus::kFound) << d.reason;
  }
  ASSERT_TRUE(pipe.appearance().ready());
  // When the same-size blue ball stands at the same place (no prior: the track is lost)
  const auto rejected = pipe.step(blue.frame.left, blue.frame.right, false, std::nullopt, t);
  // Then it is rejected for its colour
  EXPECT_NE(rejected.status, DetectionStatus::kFound) << rejected.reason;
  EXPECT_GE(rejected.rejected_by_colour, 1);
  // And the orange ball is still found
  const auto again = pipe.step(orange.frame.left, orange.frame.right, false, std::nullopt, t);
  EXPECT_EQ(again.status, DetectionStatus::kFound) << again.reason;
  // When the loss lasts longer than the timeout, Then the model is forgotten and any ball is found
  const auto later =
      pipe.step(blue.frame.left, blue.frame.right, false, std::nullopt, t + 1'100'000'000);
  EXPECT_FALSE(pipe.appearance().ready());
  EXPECT_EQ(later.status, DetectionStatus::kFound) << later.reason;
  EXPECT_EQ(later.rejected_by_colour, 0);
}

TEST(StereoPipelineAppearance, WithoutAPriorNothingIsLearnt) {
  const RenderedScene orange = render_ball(kOrange);
  StereoPipeline pipe(sb::ball_detector::BallDetectorParams{});
  ASSERT_TRUE(pipe.set_calibration(orange.calib).ok());
  for (int i = 0; i < 5; ++i) {
    const auto d =
        pipe.step(orange.frame.left, orange.frame.right, false, std::nullopt, i * kFrameNs);
    ASSERT_EQ(d.status, DetectionStatus::kFound) << d.reason;
  }
  EXPECT_EQ(pipe.appearance().samples(), 0);
}
