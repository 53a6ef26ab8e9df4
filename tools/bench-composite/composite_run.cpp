#include "composite_run.hpp"

#include "ball_detector/pipeline/stereo_pipeline.hpp"

#include <algorithm>
#include <chrono>

namespace stereoball::composite {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

double SuiteResult::found_fraction() const {
  if (balls.empty()) return 0.0;
  const auto n = std::count_if(balls.begin(), balls.end(), [](const auto& b) { return b.found; });
  return static_cast<double>(n) / static_cast<double>(balls.size());
}

double SuiteResult::median_error_of_depth() const {
  std::vector<double> e;
  for (const auto& b : balls)
    if (b.found) e.push_back(b.error_of_depth);
  return median(e);
}

double SuiteResult::median_ms() const {
  std::vector<double> t;
  for (const auto& b : balls) t.push_back(b.ms);
  return median(t);
}

ball_detector::BallDetectorParams composite_params(ball_detector::BallDetectorParams params,
                                                   double radius_m) {
  params.ball_diameter_m = 2.0 * radius_m;
  params.floor_tolerance_m = 0.0;
  return params;
}

SuiteResult run_suite(const std::vector<Background>& backgrounds,
                      const ball_detector::BallDetectorParams& params,
                      const SuiteOptions& options) {
  SuiteResult out;
  for (std::size_t i = 0; i < backgrounds.size(); ++i) {
    const Background& bg = backgrounds[i];
    // Each composited pair is a still of its own: a fresh pipeline (no history) per frame.
    const auto calib = rectified_rig_calibration(bg);
    ball_detector::StereoPipeline pipeline(params);
    if (!pipeline.set_calibration(calib).ok()) continue;
    ++out.frames_without_ball;
    const auto empty = pipeline.step(bg.left, bg.right, true);
    if (empty.status == ball_detector::DetectionStatus::kFound) {
      ++out.false_detections;
      out.false_details.push_back(bg.name + ": z " + std::to_string(empty.position_m[2]) + " m");
    }
    const auto balls =
        place_balls(bg, options.balls_per_background, options.radius_m, options.min_depth_m,
                    options.max_depth_m, options.seed + static_cast<unsigned>(i));
    for (const Ball& ball : balls) {
      const auto [left, right] = composite(bg, ball);
      pipeline = ball_detector::StereoPipeline(params);
      pipeline.set_calibration(calib);
      const auto start = std::chrono::steady_clock::now();
      const auto det = pipeline.step(left, right, true);
      BallOutcome o;
      o.background = bg.name;
      o.ball = ball;
      o.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                 .count();
      o.found = det.status == ball_detector::DetectionStatus::kFound;
      o.status = ball_detector::to_string(det.status);
      if (!o.found) o.status += ": " + det.reason;
      if (o.found) {
        o.error_m = cv::norm(det.position_m - ball.centre_m);
        o.error_of_depth = o.error_m / ball.centre_m[2];
      }
      out.balls.push_back(std::move(o));
    }
  }
  return out;
}

}  // namespace stereoball::composite
