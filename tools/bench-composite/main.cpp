// stereoball bench composite: the ball detector's stereo pipeline on real stereo backgrounds
// (OpenCV's 13 chessboard pairs through their calibration, Middlebury Aloe) with a shaded
// sphere composited into both rectified views at known 3D positions. Prints figures only.

#include "ball_detector/pipeline/detector_params_file.hpp"
#include "composite_run.hpp"
#include "stereo/io/calibration_file.hpp"

#include "common/util/cli11.hpp"

#include <cstdio>
#include <iostream>
#include <map>

namespace {

using namespace stereoball;

void print(const composite::SuiteResult& r, bool list_all) {
  std::map<std::string, std::pair<int, int>> by_colour, by_kind;  // found, total
  for (const auto& b : r.balls) {
    auto& c = by_colour[b.ball.colour];
    auto& k = by_kind[b.background == "aloe" ? "aloe" : "chessboard"];
    c.first += b.found;
    ++c.second;
    k.first += b.found;
    ++k.second;
    if (list_all || !b.found) {
      std::printf("  %-13s %-7s z %.2f m  %s", b.background.c_str(), b.ball.colour.c_str(),
                  b.ball.centre_m[2], b.status.c_str());
      if (b.found) std::printf(" error %.3f %% of depth", 100.0 * b.error_of_depth);
      std::printf("\n");
    }
  }
  int found = 0;
  for (const auto& b : r.balls) found += b.found;
  std::printf("found %d of %zu balls (%.1f %%)\n", found, r.balls.size(),
              100.0 * r.found_fraction());
  for (const auto& [name, fc] : by_colour)
    std::printf("  colour %-8s %d / %d\n", name.c_str(), fc.first, fc.second);
  for (const auto& [name, fc] : by_kind)
    std::printf("  background %-10s %d / %d\n", name.c_str(), fc.first, fc.second);
  std::printf("false detections: %d of %d pairs without a ball\n", r.false_detections,
              r.frames_without_ball);
  for (const auto& d : r.false_details) std::printf("  %s\n", d.c_str());
  std::printf("median 3D error: %.3f %% of depth; median pipeline time %.1f ms per stereo frame\n",
              100.0 * r.median_error_of_depth(), r.median_ms());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Ball detector pipeline on real stereo backgrounds with a composited ball: found "
      "rate (per colour, per background), false detections on the pairs without a "
      "ball, median 3D error as a fraction of depth, time. Figures only.",
      "stereoball-bench-composite"};
  std::string data = SB_DEFAULT_DATA_DIR;
  std::string calibration =
      std::string(SB_DEFAULT_CONFIG_DIR) + "/calibration/opencv_samples_stereo.yaml";
  std::string config = std::string(SB_DEFAULT_CONFIG_DIR) + "/ball_detector.yaml";
  composite::SuiteOptions options;
  bool list_all = false;
  app.add_option("--data", data, "folder of OpenCV's sample images")->capture_default_str();
  app.add_option("--calibration", calibration, "calibration of the chessboard pairs")
      ->capture_default_str();
  app.add_option("--config", config,
                 "ball_detector params (the diameter is set to the ball's, "
                 "the floor check off)")
      ->capture_default_str();
  app.add_option("--balls", options.balls_per_background, "balls per background")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  app.add_option("--seed", options.seed, "seed of the ball positions")->capture_default_str();
  app.add_option("--radius-m", options.radius_m, "ball radius, metres")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 1.0));
  app.add_flag("--list", list_all, "print every ball, not only the misses");
  CLI11_PARSE(app, argc, argv);
  auto calib = stereo::load_calibration(calibration);
  if (!calib) {
    std::cerr << "stereoball-bench-composite: " << calib.error() << "\n";
    return 1;
  }
  auto params = ball_detector::load_detector_params(config);
  if (!params) {
    std::cerr << "stereoball-bench-composite: " << params.error() << "\n";
    return 1;
  }
  auto backgrounds = composite::load_real_backgrounds(data, *calib);
  if (!backgrounds) {
    std::cerr << "stereoball-bench-composite: " << backgrounds.error() << "\n";
    return 1;
  }
  const auto result = composite::run_suite(
      *backgrounds, composite::composite_params(*params, options.radius_m), options);
  print(result, list_all);
  return 0;
}
