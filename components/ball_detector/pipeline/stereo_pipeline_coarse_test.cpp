// StereoPipeline's coarse-to-fine whole-frame and band searches (search/coarse_search.hpp) on
// frames rendered by the simulator at 2304x1296: the ball found is the full-width search's,
// within a pixel; a frame without a ball gives nothing; a 640-px frame is searched as before.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "ball_detector/pipeline/stereo_pipeline.hpp"
#include "simulator/core/ball_scene.hpp"
#include "simulator/core/simulator.hpp"
#include "simulator/io/scenario_file.hpp"

#include <opencv2/imgproc.hpp>

namespace sb = stereoball;
using sb::ball_detector::BallDetectorParams;
using sb::ball_detector::DetectionStatus;
using sb::ball_detector::SearchPath;
using sb::ball_detector::StereoPipeline;

namespace {

struct WideRendered {
  sb::simulator::SimFrame frame;
  sb::stereo::StereoCalibration calib;
};

// A plain room (no clutter) with a one-colour ball of radius_m at (x_m, y_m) on the floor,
// width x height.
WideRendered render_plain(double x_m, double y_m, int width_px, int height_px,
                          double radius_m = 0.11) {
  sb::simulator::SimBallSetup s;
  s.ball_x_m = x_m;
  s.ball_y_m = y_m;
  s.clutter = false;
  s.plain_room = true;
  s.uniform_ball = true;
  auto params = sb::simulator::default_sim_params();
  params.width_px = width_px;
  params.height_px = height_px;
  auto scenario = sb::simulator::make_sim_scenario(s);
  if (scenario.ball) scenario.ball->radius_m = radius_m;
  EXPECT_TRUE(sb::simulator::Simulator::check(params, scenario).ok());
  sb::simulator::Simulator sim(params, scenario);
  return {sim.step(std::nullopt, 0), sim.calibration()};
}

// One frame of a wide run: its detection, whether it is on the ball, the searches it started.
struct WideFrame {
  bool visible = false;  // the ball's centre in both images
  bool on_ball = false;  // a pair within one ball radius of the truth
  SearchPath search = SearchPath::kWholeFrame;
  std::vector<SearchPath> started;
};

// Frames first..first + frames - 1 of scenario_name (robot still) rendered width x height and
// searched as stills (1 s apart: every band) by a pipeline with params.
std::vector<WideFrame> run_wide_stills(const std::string& scenario_name, int first, int frames,
                                       int width_px, int height_px, BallDetectorParams params) {
  auto scenario = sb::simulator::load_scenario_by_name(
      scenario_name, std::string(SB_SOURCE_DIR) + "/config/scenarios");
  EXPECT_TRUE(scenario.ok()) << scenario.error();
  std::vector<WideFrame> out;
  if (!scenario.ok() || !scenario->ball) return out;
  auto sim_params = sb::simulator::default_sim_params();
  sim_params.width_px = width_px;
  sim_params.height_px = height_px;
  sb::simulator::Simulator sim(sim_params, *scenario);
  params.ball_diameter_m = 2.0 * scenario->ball->radius_m;
  StereoPipeline pipeline(params);
  EXPECT_TRUE(pipeline.set_calibration(sim.calibration()).ok());
  std::vector<SearchPath> started;
  pipeline.set_search_observer([&](SearchPath path, bool start) {
    if (start) started.push_back(path);
  });
  for (int i = 0; i < first; ++i) (void)sim.step(std::nullopt, i * sim.frame_period_ns());
  for (int i = first; i < first + frames; ++i) {
    const auto f = sim.step(std::nullopt, i * sim.frame_period_ns());
    started.clear();
    const auto det = pipeline.step(f.left, f.right, false, std::nullopt, i * 1'000'000'000LL);
    const cv::Vec3d truth(f.truth.ball_camera_m.x, f.truth.ball_camera_m.y,
                          f.truth.ball_camera_m.z);
    WideFrame r;
    r.visible = f.truth.ball_visible_left && f.truth.ball_visible_right;
    r.on_ball = det.status == DetectionStatus::kFound &&
                cv::norm(det.position_m - truth) < f.truth.ball_radius_m;
    r.search = det.search;
    r.started = started;
    out.push_back(r);
  }
  return out;
}

bool started_search(const WideFrame& f, SearchPath path) {
  return std::find(f.started.begin(), f.started.end(), path) != f.started.end();
}

// The shipped settings with coarse to fine at target_width_px (0 = off).
BallDetectorParams with_target(int target_width_px) {
  BallDetectorParams p;
  p.coarse_to_fine.target_width_px = target_width_px;
  return p;
}

// One rendered raw pair through a full-width pipeline (first) and one with COARSE's settings.
std::pair<sb::ball_detector::StereoDetection, sb::ball_detector::StereoDetection> full_and_coarse(
    const WideRendered& r, const BallDetectorParams& coarse) {
  StereoPipeline full_pipeline(with_target(0));
  StereoPipeline coarse_pipeline(coarse);
  EXPECT_TRUE(full_pipeline.set_calibration(r.calib).ok());
  EXPECT_TRUE(coarse_pipeline.set_calibration(r.calib).ok());
  return {full_pipeline.step(r.frame.left, r.frame.right, false),
          coarse_pipeline.step(r.frame.left, r.frame.right, false)};
}

}  // namespace

TEST(StereoPipelineCoarse, GivenA2304FrameThenTheSameBallAsTheFullWidthSearch) {
  for (const auto& [x_m, y_m] : {std::pair{1.5, 0.0}, std::pair{2.5, 0.3}}) {
    // Given a rendered 2304x1296 pair, searched at full width and coarse to fine (level 2)
    const WideRendered r = render_plain(x_m, y_m, 2304, 1296);
    // When each processes the raw pair
    const auto [a, b] = full_and_coarse(r, with_target(640));
    // Then both find it by the whole-frame search, at the same place within a pixel
    ASSERT_EQ(a.status, DetectionStatus::kFound) << a.reason;
    ASSERT_EQ(b.status, DetectionStatus::kFound) << b.reason;
    EXPECT_EQ(b.search, SearchPath::kWholeFrame);
    EXPECT_NEAR(b.left.x_px, a.left.x_px, 1.0);
    EXPECT_NEAR(b.left.y_px, a.left.y_px, 1.0);
    EXPECT_NEAR(b.left.radius_px, a.left.radius_px, 1.0);
    EXPECT_NEAR(b.right.x_px, a.right.x_px, 1.0);
    EXPECT_LT(std::abs(b.position_m[2] - a.position_m[2]), 0.02 * a.position_m[2]);
  }
}

TEST(StereoPipelineCoarse, GivenNoBallThenNothingFoundCoarseToFine) {
  // Given a 2304x1296 plain room with the ball out of view (far to the side)
  const WideRendered r = render_plain(1.5, 2.5, 2304, 1296);
  ASSERT_FALSE(r.frame.truth.ball_visible_left);
  StereoPipeline coarse(with_target(640));
  ASSERT_TRUE(coarse.set_calibration(r.calib).ok());
  // When searched coarse to fine (the reduced eye and its bands, then the whole frame at full
  // width)
  const auto det = coarse.step(r.frame.left, r.frame.right, false);
  // Then nothing is reported found, and the last search was the full-width whole frame (its
  // bands were the reduced eye's: not searched again at full width)
  EXPECT_NE(det.status, DetectionStatus::kFound) << det.reason;
  EXPECT_EQ(det.search, SearchPath::kWholeFrame);
}

TEST(StereoPipelineCoarse, GivenAReferenceWidthFrameNotByRadiusThenSearchedAsWithoutIt) {
  // Given the simulator's 640x480 pair with coarse to fine on (target 640, not by radius) and off
  const WideRendered r = render_plain(1.5, 0.0, 640, 480);
  StereoPipeline off(with_target(0));
  BallDetectorParams not_by_radius = with_target(640);
  not_by_radius.coarse_by_radius = false;
  StereoPipeline on(not_by_radius);
  ASSERT_TRUE(off.set_calibration(r.calib).ok());
  ASSERT_TRUE(on.set_calibration(r.calib).ok());
  // When each processes it
  const auto a = off.step(r.frame.left, r.frame.right, false);
  const auto b = on.step(r.frame.left, r.frame.right, false);
  // Then the detections are the same to the bit
  ASSERT_EQ(a.status, DetectionStatus::kFound) << a.reason;
  EXPECT_EQ(b.status, a.status);
  EXPECT_EQ(b.left.x_px, a.left.x_px);
  EXPECT_EQ(b.left.y_px, a.left.y_px);
  EXPECT_EQ(b.left.radius_px, a.left.radius_px);
  EXPECT_EQ(b.position_m, a.position_m);
}

TEST(StereoPipelineCoarse, GivenFramesAlreadyShrunkToTheWorkingSizeThenTheSameDetection) {
  // Given a rendered 2304x1296 pair, searched at the working width 1280 (shrunk by 2), and the
  // same pair shrunk by its source as the pipeline shrinks it (a JPEG decoded reduced)
  const WideRendered r = render_plain(1.5, 0.0, 2304, 1296);
  BallDetectorParams params = with_target(640);
  params.working_width_px = 1280;
  StereoPipeline a(params), b(params);
  ASSERT_TRUE(a.set_calibration(r.calib).ok());
  ASSERT_TRUE(b.set_calibration(r.calib).ok());
  ASSERT_EQ(a.working_reduction(), 2);
  cv::Mat left, right;
  cv::resize(r.frame.left, left, a.working_size(), 0, 0, cv::INTER_AREA);
  cv::resize(r.frame.right, right, a.working_size(), 0, 0, cv::INTER_AREA);
  // When one pipeline gets the full frames and the other the shrunk ones
  const auto full = a.step(r.frame.left, r.frame.right, false);
  const auto shrunk = b.step(left, right, false);
  // Then both report the same ball in the calibration's pixels, to the bit
  ASSERT_EQ(full.status, DetectionStatus::kFound) << full.reason;
  EXPECT_EQ(shrunk.status, full.status) << shrunk.reason;
  EXPECT_EQ(shrunk.left.x_px, full.left.x_px);
  EXPECT_EQ(shrunk.left.radius_px, full.left.radius_px);
  EXPECT_EQ(shrunk.position_m, full.position_m);
  // And frames of neither size are refused
  cv::Mat other;
  cv::resize(r.frame.left, other, cv::Size(1000, 562));
  EXPECT_EQ(b.step(other, other, false).status, DetectionStatus::kBadFrame);
}

TEST(StereoPipelineCoarse, GivenFramesSearchedAtTheirOwnSizeThenNoWorkingReduction) {
  // Given a 640x480 calibration (not shrunk) and a 2304x1296 one with working_width_px 0
  const WideRendered small = render_plain(1.5, 0.0, 640, 480);
  BallDetectorParams params = with_target(640);
  StereoPipeline a(params);
  ASSERT_TRUE(a.set_calibration(small.calib).ok());
  params.working_width_px = 0;
  StereoPipeline b(params);
  const WideRendered wide = render_plain(1.5, 0.0, 2304, 1296);
  ASSERT_TRUE(b.set_calibration(wide.calib).ok());
  // When asked by how much a source may reduce their frames
  // Then by nothing
  EXPECT_EQ(a.working_reduction(), 1);
  EXPECT_EQ(b.working_reduction(), 1);
}

// A wide frame whose ball only a radius band finds at full width (a plate on the far wall
// outscores it over the whole range): coarse to fine, the reduced eye's bands find it in the
// whole frame's first try, and no frame searches the bands again at full width.
TEST(StereoPipelineCoarse, GivenABallOnlyTheBandsFindThenTheReducedEyesBandsFindIt) {
  // Given ball_rolling_across rendered at 2304x1296 (frames 18-23: the ball beside the box),
  // searched at full width and coarse to fine
  const int first = 18, frames = 6;
  const auto full =
      run_wide_stills("ball_rolling_across", first, frames, 2304, 1296, with_target(0));
  const auto coarse =
      run_wide_stills("ball_rolling_across", first, frames, 2304, 1296, with_target(640));
  ASSERT_EQ(full.size(), static_cast<std::size_t>(frames));
  ASSERT_EQ(coarse.size(), full.size());
  // When the full-width search needs its bands on some frames
  int band_finds = 0;
  for (int i = 0; i < frames; ++i) {
    if (!(full[i].on_ball && full[i].search == SearchPath::kRadiusBands)) continue;
    ++band_finds;
    // Then coarse to fine finds the same ball there by the whole frame's (reduced) search
    EXPECT_TRUE(coarse[i].on_ball) << "frame " << first + i;
    EXPECT_EQ(coarse[i].search, SearchPath::kWholeFrame) << "frame " << first + i;
  }
  ASSERT_GE(band_finds, 1) << "premise: at full width the bands find what the whole range misses";
  // And no frame searched coarse to fine started the full-width bands
  for (int i = 0; i < frames; ++i)
    EXPECT_FALSE(started_search(coarse[i], SearchPath::kRadiusBands)) << "frame " << first + i;
}

// A wide frame whose reduced-eye pair is judged weak (coarse_to_fine.min_pair_score above any
// pair score): the frame still reaches the full-width whole-frame search, whose answer is the
// full-width search's own.
TEST(StereoPipelineCoarse, GivenAWeakCoarsePairThenTheFullWidthSearchAnswers) {
  // Given a rendered 2304x1296 pair, searched at full width, and coarse to fine with every
  // reduced-eye pair too weak to answer
  const WideRendered r = render_plain(1.5, 0.0, 2304, 1296);
  BallDetectorParams weak = with_target(640);
  weak.coarse_min_pair_score = 1.0;
  // When each processes the raw pair
  const auto [a, b] = full_and_coarse(r, weak);
  // Then both find the ball by the whole frame at full width: the same detection to the bit
  ASSERT_EQ(a.status, DetectionStatus::kFound) << a.reason;
  ASSERT_EQ(b.status, DetectionStatus::kFound) << b.reason;
  EXPECT_EQ(b.search, SearchPath::kWholeFrame);
  EXPECT_EQ(b.left.x_px, a.left.x_px);
  EXPECT_EQ(b.left.y_px, a.left.y_px);
  EXPECT_EQ(b.left.radius_px, a.left.radius_px);
  EXPECT_EQ(b.right.x_px, a.right.x_px);
  EXPECT_EQ(b.position_m, a.position_m);
}

// Coarse to fine by radius (coarse_to_fine.by_radius, off by default): the whole-frame search
// votes on the halved eye for the radii it resolves (7 px and up at full width) and leaves the
// smaller ones to the full-width radius bands.
TEST(StereoPipelineCoarse, GivenA640FrameByRadiusThenItsLargeBallIsFoundThroughTheHalvedEye) {
  for (const auto& [x_m, y_m] : {std::pair{1.5, 0.0}, std::pair{2.5, 0.3}}) {
    // Given a rendered 640x480 pair (a ball of 20-40 px radius), searched at full width and by
    // radius
    const WideRendered r = render_plain(x_m, y_m, 640, 480);
    BallDetectorParams by_radius = with_target(640);
    by_radius.coarse_by_radius = true;
    StereoPipeline pipeline(by_radius);
    ASSERT_TRUE(pipeline.set_calibration(r.calib).ok());
    std::vector<SearchPath> started;
    pipeline.set_search_observer([&](SearchPath path, bool start) {
      if (start) started.push_back(path);
    });
    // When each processes the raw pair
    StereoPipeline full(with_target(0));
    ASSERT_TRUE(full.set_calibration(r.calib).ok());
    const auto a = full.step(r.frame.left, r.frame.right, false);
    const auto b = pipeline.step(r.frame.left, r.frame.right, false);
    // Then the halved eye's whole-frame search finds the full-width search's ball, within a
    // pixel, without the radius bands
    ASSERT_EQ(a.status, DetectionStatus::kFound) << a.reason;
    ASSERT_EQ(b.status, DetectionStatus::kFound) << b.reason;
    ASSERT_GE(b.left.radius_px, 7.0) << "premise: a radius the halved eye resolves";
    EXPECT_EQ(b.search, SearchPath::kWholeFrame);
    EXPECT_EQ(std::count(started.begin(), started.end(), SearchPath::kRadiusBands), 0);
    EXPECT_NEAR(b.left.x_px, a.left.x_px, 1.0);
    EXPECT_NEAR(b.left.y_px, a.left.y_px, 1.0);
    EXPECT_NEAR(b.left.radius_px, a.left.radius_px, 1.0);
    EXPECT_LT(std::abs(b.position_m[2] - a.position_m[2]), 0.02 * a.position_m[2]);
  }
}

TEST(StereoPipelineCoarse, GivenA640FrameByRadiusThenASmallBallIsFoundAtFullWidth) {
  // Given a rendered 640x480 pair with a 4 cm ball 2 m ahead: about 5 px in radius, below what
  // the halved eye resolves (min_coarse_radius_px 3.5 there: 7 px); no colour seeds (they would
  // find this one-colour ball in the whole-frame search without voting)
  const WideRendered r = render_plain(2.0, 0.0, 640, 480, 0.02);
  BallDetectorParams params = with_target(640);
  params.ball_diameter_m = 0.04;
  params.colour_seeds.enabled = false;
  params.coarse_by_radius = true;
  StereoPipeline pipeline(params);
  ASSERT_TRUE(pipeline.set_calibration(r.calib).ok());
  // When it processes the raw pair as a still (every radius band)
  const auto det = pipeline.step(r.frame.left, r.frame.right, false);
  // Then the full-width radius bands find it, where it is
  ASSERT_EQ(det.status, DetectionStatus::kFound) << det.reason;
  EXPECT_EQ(det.search, SearchPath::kRadiusBands);
  EXPECT_LT(det.left.radius_px, 7.0);
  const cv::Vec3d truth(r.frame.truth.ball_camera_m.x, r.frame.truth.ball_camera_m.y,
                        r.frame.truth.ball_camera_m.z);
  EXPECT_LT(cv::norm(det.position_m - truth), r.frame.truth.ball_radius_m);
}
