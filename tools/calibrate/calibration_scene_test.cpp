// End to end against the simulator's true rig: the calibration scene is rendered, the board
// detected in every frame, still poses selected (or not), the rig calibrated with the
// calibrate tool's library, and the result compared with the truth.

#include "simulator/core/simulator.hpp"
#include "stereo/core/board_calibration.hpp"
#include "stereo/core/still_board.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace stereoball {
namespace {

namespace sim = simulator;
constexpr int64_t kMs = 1'000'000;

// What one calibration got right and wrong against the truth.
struct Outcome {
  int pairs = 0;                  // pairs given to the calibration
  int dropped = 0;                // pairs the calibration dropped as inconsistent
  double focal_error_pct = 0;     // worst of fx, fy of both eyes, % of the truth
  double baseline_error_pct = 0;  // |T| against the true baseline, %
  double truth_row_error_px = 0;  // mean rectified row error of the true corner projections
  double own_row_error_px = 0;    // the calibration's own figure on the pairs it used
};

sim::SimParams sim_params() {
  sim::SimParams p;
  p.width_px = 640;
  p.height_px = 480;
  p.frame_rate_hz = 10.0;
  return p;
}

sim::Scenario scene(double eye_skew_s) {
  sim::Scenario s;
  s.name = "calibration_test";
  s.seed = 11;
  sim::CalibrationScene c;
  sim::BoardPoseRanges r;
  r.count = 18;
  r.hold_s = 0.6;
  r.move_s = 0.6;
  r.seed = 3;
  c.random_poses = r;
  c.eye_skew_s = eye_skew_s;
  s.calibration = c;
  s.duration_s = c.duration_s();
  return s;
}

stereo::BoardCalibrationParams board_params(const sim::CalibrationBoard& b) {
  stereo::BoardCalibrationParams p;
  p.inner_corners = {b.cols, b.rows};
  p.square_m = b.square_m;
  return p;
}

// Every frame's detected corners (empty where the board was not found), per eye.
struct Detections {
  std::vector<int64_t> left_ns, right_ns;
  std::vector<std::vector<cv::Point2f>> left, right;
};

Detections render_and_detect(const sim::Scenario& scenario, sim::Simulator& s) {
  const auto params = board_params(s.calibration_scene()->board);
  Detections d;
  const int64_t end_ns = static_cast<int64_t>(scenario.duration_s * 1e9);
  for (int64_t t = 0; t <= end_ns; t += s.frame_period_ns()) {
    const sim::SimFrame f = s.step(std::nullopt, t);
    d.left_ns.push_back(f.sim_time_ns);
    d.right_ns.push_back(f.right_time_ns);
    d.left.push_back(
        stereo::find_board_corners(f.left, params).value_or(std::vector<cv::Point2f>{}));
    d.right.push_back(
        stereo::find_board_corners(f.right, params).value_or(std::vector<cv::Point2f>{}));
  }
  return d;
}

std::vector<stereo::PairCorners> still_pairs(const Detections& d) {
  stereo::StillBoardParams p;
  p.max_motion_px = 0.5;
  p.still_ns = 250 * kMs;
  stereo::StillBoardSelector selector(p);
  std::vector<stereo::PairCorners> pairs;
  const auto take = [&](const std::optional<stereo::StillPose>& pose) {
    if (!pose) return;
    stereo::PairCorners pc{"still " + std::to_string(pairs.size()), pose->left_px, pose->right_px};
    stereo::align_corner_order(pc.left_px, pc.right_px);
    pairs.push_back(std::move(pc));
  };
  // Each eye's detections in capture order (the right eye may run ahead or behind).
  for (std::size_t i = 0; i < d.left.size(); ++i) {
    take(selector.add(stereo::Eye::kLeft, d.left_ns[i], d.left[i]));
    take(selector.add(stereo::Eye::kRight, d.right_ns[i], d.right[i]));
  }
  return pairs;
}

// Every frame in which both eyes found the board, one in every `every` of them.
std::vector<stereo::PairCorners> all_pairs(const Detections& d, int every) {
  std::vector<stereo::PairCorners> pairs;
  int seen = 0;
  for (std::size_t i = 0; i < d.left.size(); ++i) {
    if (d.left[i].empty() || d.right[i].empty() || seen++ % every != 0) continue;
    stereo::PairCorners pc{"frame " + std::to_string(i), d.left[i], d.right[i]};
    stereo::align_corner_order(pc.left_px, pc.right_px);
    pairs.push_back(std::move(pc));
  }
  return pairs;
}

// The exact image points of every hold's corners in both eyes (noise-free matched points).
std::vector<stereo::PairCorners> truth_pairs(const sim::Simulator& s) {
  const auto& scene = *s.calibration_scene();
  std::vector<stereo::PairCorners> out;
  for (const auto& h : scene.holds) {
    stereo::PairCorners pc;
    for (const auto& p : sim::board_corners_px(s.rig(), sim::Eye::kLeft, scene.board, h.pose))
      pc.left_px.emplace_back(p);
    for (const auto& p : sim::board_corners_px(s.rig(), sim::Eye::kRight, scene.board, h.pose))
      pc.right_px.emplace_back(p);
    out.push_back(std::move(pc));
  }
  return out;
}

double pct(double got, double truth) {
  return 100.0 * std::abs(got - truth) / std::abs(truth);
}

Outcome calibrate(const std::vector<stereo::PairCorners>& pairs, const sim::Simulator& s,
                  stereo::BoardCalibrationParams params) {
  Outcome o;
  o.pairs = static_cast<int>(pairs.size());
  const auto r = stereo::calibrate_stereo(pairs, {640, 480}, params);
  EXPECT_TRUE(r) << (r ? "" : r.error());
  if (!r) return o;
  const auto& c = r->calibration;
  const auto& t = s.calibration();
  o.dropped = static_cast<int>(r->dropped.size());
  o.focal_error_pct = std::max({pct(c.k1(0, 0), t.k1(0, 0)), pct(c.k1(1, 1), t.k1(1, 1)),
                                pct(c.k2(0, 0), t.k2(0, 0)), pct(c.k2(1, 1), t.k2(1, 1))});
  o.baseline_error_pct = pct(stereo::baseline_m(c), stereo::baseline_m(t));
  o.truth_row_error_px = stereo::rectified_row_error_px(c, truth_pairs(s)).first;
  o.own_row_error_px = r->mean_rectified_row_error_px;
  return o;
}

void print(const char* what, const Outcome& o) {
  std::printf(
      "%-34s pairs %3d (dropped %d): focal error %.3f %%, baseline error %.3f %%, row error "
      "%.3f px (true corners), %.3f px (own pairs)\n",
      what, o.pairs, o.dropped, o.focal_error_pct, o.baseline_error_pct, o.truth_row_error_px,
      o.own_row_error_px);
}

TEST(CalibrationScene, SynchronisedEyesCalibrateToTheTruth) {
  // Given the simulator's calibration scene with both eyes captured at once
  const sim::Scenario scenario = scene(0.0);
  ASSERT_TRUE(sim::Simulator::check(sim_params(), scenario));
  sim::Simulator s(sim_params(), scenario);
  // When the still poses are selected from the detections and calibrated
  const auto pairs = still_pairs(render_and_detect(scenario, s));
  const Outcome o = calibrate(pairs, s, board_params(s.calibration_scene()->board));
  print("synchronised, still-board rule:", o);
  // Then one pose per hold is taken and the calibration matches the true rig
  EXPECT_GE(o.pairs, 15);
  EXPECT_LE(o.pairs, 18);
  EXPECT_LT(o.focal_error_pct, 0.5);
  EXPECT_LT(o.baseline_error_pct, 0.5);
  EXPECT_LT(o.truth_row_error_px, 0.2);
  EXPECT_LT(o.own_row_error_px, 0.2);
}

TEST(CalibrationScene, FreeRunningEyesNeedTheStillBoardRule) {
  // Given the same scene with the right eye capturing 15 ms after the left
  const sim::Scenario scenario = scene(0.015);
  sim::Simulator s(sim_params(), scenario);
  const Detections d = render_and_detect(scenario, s);
  // When the still poses are selected
  const Outcome still = calibrate(still_pairs(d), s, board_params(s.calibration_scene()->board));
  print("free-running 15 ms, still-board rule:", still);
  // Then the result is as good as with synchronised eyes
  EXPECT_GE(still.pairs, 15);
  EXPECT_LT(still.focal_error_pct, 0.5);
  EXPECT_LT(still.baseline_error_pct, 0.5);
  EXPECT_LT(still.truth_row_error_px, 0.2);
  EXPECT_LT(still.own_row_error_px, 0.2);
  // And when frames are taken regardless of motion (every fifth frame showing the board to
  // both eyes, every pair kept), the rectified rows disagree measurably more
  auto keep_all = board_params(s.calibration_scene()->board);
  keep_all.outlier_ratio = 0.0;
  const Outcome all = calibrate(all_pairs(d, 5), s, keep_all);
  print("free-running 15 ms, every 5th frame:", all);
  EXPECT_GT(all.own_row_error_px, 2.0 * still.own_row_error_px);
  EXPECT_GT(all.truth_row_error_px, 2.0 * still.truth_row_error_px);
  // and the focal length or the baseline misses the 0.5 % target
  EXPECT_GT(std::max(all.focal_error_pct, all.baseline_error_pct), 0.5);
}

}  // namespace
}  // namespace stereoball
