#include "simulator/core/simulator.hpp"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <thread>

namespace stereoball::simulator {
namespace {

constexpr int64_t kS = 1'000'000'000;

SimParams small_params() {
  SimParams p;
  p.width_px = 352;
  p.height_px = 288;
  p.sensor.noise_sigma_dn = 3.0;
  return p;
}

Scenario rolling_scene(uint64_t seed) {
  Scenario s;
  s.name = "test_rolling";
  s.seed = seed;
  s.ball = BallSpec{};
  s.ball->x_m = 2.0, s.ball->y_m = -0.5, s.ball->vy_mps = 0.4;
  s.boxes.push_back({3.0, 1.2, 0.5, 0.5, 0.5, 0.0, {60, 90, 140}});
  s.plates.push_back({{5.99, -0.5, 1.2}, {-1, 0, 0}, 0.15, 0.02, {230, 110, 20}, {250, 250, 250}});
  s.door_frames.push_back({6.0, 1.5, false, 0.9, 2.0, 0.08, 0.12, {240, 240, 235}, {130, 85, 50}});
  return s;
}

bool same(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

TEST(Simulator, SameSeedGivesByteIdenticalFrames) {
  // Given two simulators with the same params and seed
  const SimParams p = small_params();
  const Scenario s = rolling_scene(42);
  ASSERT_TRUE(Simulator::check(p, s).ok());
  Simulator a(p, s), b(p, s);
  // When both run the same frames with the same commands
  for (int i = 0; i < 4; ++i) {
    const int64_t t = i * a.frame_period_ns();
    const VelocityCommand cmd{0.2, 0.3, t};
    const SimFrame fa = a.step(cmd, t);
    const SimFrame fb = b.step(cmd, t);
    // Then every frame is byte-identical, including the noise
    ASSERT_TRUE(same(fa.left, fb.left)) << "frame " << i;
    ASSERT_TRUE(same(fa.right, fb.right)) << "frame " << i;
    EXPECT_EQ(fa.truth.robot.x_m, fb.truth.robot.x_m);
  }
}

TEST(Simulator, EyesRenderedAtOnceGiveTheSameFramesAsInTurn) {
  // Given two simulators of one scene, sharp and with motion blur; one renders its eyes in
  // turn, the other on two threads (as the simulator node does)
  const auto on_two_threads = [](const std::function<void()>& a, const std::function<void()>& b) {
    std::thread left(a);
    b();
    left.join();
  };
  for (int blur : {1, 3}) {
    SimParams p = small_params();
    p.sensor.motion_blur_subframes = blur;
    const Scenario s = rolling_scene(7);
    Simulator in_turn(p, s), at_once(p, s);
    // When both step through the same frames and commands
    for (int i = 0; i < 5; ++i) {
      const int64_t t = (i + 1) * in_turn.frame_period_ns();
      const VelocityCommand cmd{0.3, -0.4, t};
      const SimFrame a = in_turn.step(cmd, t);
      const SimFrame b = at_once.step(cmd, t, on_two_threads);
      // Then each eye and the ground truth are identical
      ASSERT_TRUE(same(a.left, b.left)) << "blur " << blur << " frame " << i;
      ASSERT_TRUE(same(a.right, b.right)) << "blur " << blur << " frame " << i;
      EXPECT_EQ(a.truth.robot.x_m, b.truth.robot.x_m);
      EXPECT_EQ(a.truth.ball_world_m.y, b.truth.ball_world_m.y);
      // And each eye shows its own view (the threads did not render one eye twice)
      EXPECT_FALSE(same(b.left, b.right));
    }
  }
}

TEST(Simulator, ACopyOfAFreshSimulatorRunsLikeANewOne) {
  // Given a fresh simulator kept unused and a copy of it (the node restarts a looped scenario
  // from such a copy), with motion blur so the scratch images are used too
  SimParams p = small_params();
  p.sensor.motion_blur_subframes = 3;
  const Scenario s = rolling_scene(11);
  const Simulator pristine(p, s);
  Simulator used(pristine);
  for (int i = 0; i < 3; ++i) used.step(VelocityCommand{0.4, 0.2, 0}, i * used.frame_period_ns());
  // When a second copy and a newly built simulator step through the same frames
  Simulator copy(pristine), built(p, s);
  for (int i = 0; i < 4; ++i) {
    const int64_t t = i * built.frame_period_ns();
    const VelocityCommand cmd{0.2, -0.3, t};
    const SimFrame a = copy.step(cmd, t);
    const SimFrame b = built.step(cmd, t);
    // Then the frames and ground truth are identical (the first copy's run left no trace)
    ASSERT_TRUE(same(a.left, b.left)) << "frame " << i;
    ASSERT_TRUE(same(a.right, b.right)) << "frame " << i;
    EXPECT_EQ(a.seq, b.seq);
    EXPECT_EQ(a.truth.robot.x_m, b.truth.robot.x_m);
    EXPECT_EQ(a.truth.ball_world_m.y, b.truth.ball_world_m.y);
  }
}

TEST(Simulator, DifferentSeedChangesOnlyTheNoise) {
  // Given two simulators that differ only in the seed
  const SimParams p = small_params();
  Simulator a(p, rolling_scene(1)), b(p, rolling_scene(2));
  // When one frame is rendered
  const SimFrame fa = a.step(std::nullopt, 0);
  const SimFrame fb = b.step(std::nullopt, 0);
  // Then images differ, but only by noise-sized amounts
  EXPECT_FALSE(same(fa.left, fb.left));
  cv::Mat diff;
  cv::absdiff(fa.left, fb.left, diff);
  EXPECT_LT(cv::mean(diff)[0], 6.0);
}

TEST(Simulator, GroundTruthTracksABallRollingOutOfViewToTheRight) {
  // Given a ball rolling toward the robot's right (-y) at 1 m/s, 1.5 m ahead
  SimParams p = small_params();
  p.sensor.noise_sigma_dn = 0.0;
  Scenario s;
  s.ball = BallSpec{};
  s.ball->x_m = 1.5, s.ball->y_m = 0.0, s.ball->vy_mps = -1.0;
  Simulator sim(p, s);
  // When the simulation runs
  const SimFrame first = sim.step(std::nullopt, 0);
  const SimFrame later = sim.step(std::nullopt, 2 * kS);
  // Then the ball is first visible in both eyes near the centre, then out of view on the right
  EXPECT_TRUE(first.truth.ball_visible_left && first.truth.ball_visible_right);
  EXPECT_FALSE(later.truth.ball_visible_left);
  EXPECT_LT(later.truth.ball_world_m.y, -1.0);
  EXPECT_GT(later.truth.ball_camera_m.x, 1.0);  // camera x points right
}

TEST(Simulator, TurningLeftMovesAStraightAheadBallRightInTheImage) {
  // Given a still ball straight ahead
  SimParams p = small_params();
  Scenario s;
  s.ball = BallSpec{};
  s.ball->x_m = 2.0, s.ball->y_m = 0.0;
  Simulator sim(p, s);
  const SimFrame before = sim.step(std::nullopt, 0);
  // When the robot turns left (positive angular velocity) for a short while
  const SimFrame after = sim.step(VelocityCommand{0.0, 0.5, 0}, kS / 2);
  // Then yaw increased and the ball moved right in the image
  EXPECT_GT(after.truth.robot.yaw_rad, 0.05);
  EXPECT_GT(after.truth.ball_left_px.x, before.truth.ball_left_px.x + 10);
}

TEST(Simulator, LightingChangeDarkensTheImage) {
  // Given a scenario whose light dims between 1 s and 2 s
  SimParams p = small_params();
  Scenario s = rolling_scene(3);
  s.lighting = {{1.0, 0.45, 0.65, 1.0}, {2.0, 0.2, 0.3, 1.0}};
  Simulator sim(p, s);
  // When frames before and after are compared
  const double bright = cv::mean(sim.step(std::nullopt, 0).left)[1];
  const double dark = cv::mean(sim.step(std::nullopt, 3 * kS).left)[1];
  // Then the later frame is clearly darker
  EXPECT_LT(dark, 0.7 * bright);
}

TEST(Simulator, MotionBlurSmearsAMovingBallButKeepsTimeConsistent) {
  // Given a fast ball rendered with and without motion blur
  SimParams sharp = small_params();
  sharp.sensor.noise_sigma_dn = 0.0;
  SimParams blurred = sharp;
  blurred.sensor.motion_blur_subframes = 4;
  blurred.sensor.shutter_s = 0.03;
  Scenario s;
  s.ball = BallSpec{};
  s.ball->x_m = 1.5, s.ball->vy_mps = 3.0;
  Simulator a(sharp, s), b(blurred, s);
  const SimFrame fa = a.step(std::nullopt, kS / 10);
  const SimFrame fb = b.step(std::nullopt, kS / 10);
  // Then images differ while the ground truth (end of exposure) is identical
  EXPECT_FALSE(same(fa.left, fb.left));
  EXPECT_NEAR(fa.truth.ball_world_m.y, fb.truth.ball_world_m.y, 1e-9);
}

TEST(Simulator, InvalidParamsAreReportedByName) {
  // Given a negative baseline
  SimParams p;
  p.rig.baseline_m = -0.1;
  // Then the check names the field
  const auto err = Simulator::check(p, Scenario{});
  ASSERT_FALSE(err.ok());
  EXPECT_NE(err.error().find("rig.baseline_m"), std::string::npos);
}

TEST(Simulator, InvalidScenarioIsReportedByName) {
  // Given a ball outside the room
  Scenario s;
  s.ball = BallSpec{};
  s.ball->x_m = 50.0;
  // Then the check names the field
  const auto err = Simulator::check(SimParams{}, s);
  ASSERT_FALSE(err.ok());
  EXPECT_NE(err.error().find("ball.x_m"), std::string::npos);
}

}  // namespace
}  // namespace stereoball::simulator
