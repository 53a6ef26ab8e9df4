// stereoball-bench-stereo: prints stereo-geometry figures (never asserts):
// LUT rectification time per 640x480 pair, point-rectify time, synthetic
// depth error vs the noise bound, and the row check on the real Aloe pair.

#include "stereo/core/epipolar.hpp"
#include "stereo/core/rectifier.hpp"
#include "stereo/core/row_check.hpp"
#include "stereo/core/synthetic_rig.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include "common/util/cli11.hpp"

#include <chrono>
#include <cstdio>
#include <functional>
#include <iostream>
#include <string>

namespace {

using namespace stereoball::stereo;
using Clock = std::chrono::steady_clock;

// Mean wall time of fn over iterations after one warm-up call, microseconds.
double mean_us(int iterations, const std::function<void()>& fn) {
  fn();
  const auto t0 = Clock::now();
  for (int i = 0; i < iterations; ++i) fn();
  const std::chrono::duration<double, std::micro> dt = Clock::now() - t0;
  return dt.count() / iterations;
}

cv::Mat noise_image(cv::Size size, int type) {
  cv::Mat m(size, type);
  cv::randu(m, cv::Scalar::all(0), cv::Scalar::all(255));
  return m;
}

void bench_rectification(int iterations) {
  const SyntheticRig rig = default_synthetic_rig();
  const StereoCalibration calib = rig.calibration();
  const double build_us = mean_us(5, [&] { (void)Rectifier::create(calib); });
  const Rectifier rect = Rectifier::create(calib).value();
  std::printf("LUT build (both eyes, 640x480, fixed-point CV_16SC2): %.2f ms\n", build_us / 1e3);
  for (int type : {CV_8UC3, CV_8UC1}) {
    const cv::Mat left = noise_image(rig.size, type), right = noise_image(rig.size, type);
    cv::Mat lo, ro;
    const double lut = mean_us(iterations, [&] { rect.rectify(left, right, lo, ro); });
    // For comparison: float maps, and rebuilding the maps every frame (no look-up table).
    cv::Mat fx1, fy1, fx2, fy2;
    cv::initUndistortRectifyMap(cv::Mat(calib.k1), cv::Mat(calib.d1), cv::Mat(calib.r1),
                                cv::Mat(calib.p1), rig.size, CV_32FC1, fx1, fy1);
    cv::initUndistortRectifyMap(cv::Mat(calib.k2), cv::Mat(calib.d2), cv::Mat(calib.r2),
                                cv::Mat(calib.p2), rig.size, CV_32FC1, fx2, fy2);
    const double flt = mean_us(iterations, [&] {
      cv::remap(left, lo, fx1, fy1, cv::INTER_LINEAR);
      cv::remap(right, ro, fx2, fy2, cv::INTER_LINEAR);
    });
    const double no_lut = mean_us(std::max(1, iterations / 10), [&] {
      (void)Rectifier::create(calib)->rectify(left, right, lo, ro);
    });
    std::printf(
        "rectify 640x480 %s pair: LUT fixed-point %.3f ms | float maps %.3f ms | "
        "maps rebuilt per frame %.3f ms\n",
        type == CV_8UC3 ? "BGR " : "grey", lut / 1e3, flt / 1e3, no_lut / 1e3);
  }
  cv::RNG rng(3);
  const double pts_us = mean_us(iterations * 50, [&] {
    const cv::Point2d p(rng.uniform(0.0, 640.0), rng.uniform(0.0, 480.0));
    (void)rect.rectify_point(Eye::kLeft, p);
    (void)rect.rectify_point(Eye::kRight, p);
  });
  std::printf("point-rectify one centre pair (both eyes, undistortPoints R1/P1, R2/P2): %.2f us\n",
              pts_us);
}

void bench_depth(int points) {
  const SyntheticRig rig = default_synthetic_rig();
  const StereoCalibration calib = rig.calibration();
  std::printf(
      "synthetic rig: f_rect %.1f px, B %.4f m, sigma 0.1 px per pixel coordinate, %d "
      "points per depth\n",
      focal_px(calib), baseline_m(calib), points);
  for (double z : {1.0, 2.0}) {
    const DepthErrorFigures f = measure_depth_error(rig, z, 0.1, points, 42);
    std::printf(
        "  Z = %.1f m: RMS depth error %.3f mm (%.4f %%), bound Z^2*d_disp/(f*B) = %.3f mm "
        "(d_disp %.3f px), ratio %.3f\n",
        z, f.rms_error_m * 1e3, 100.0 * f.rms_error_m / z, f.bound_m * 1e3, f.d_disparity_px,
        f.rms_error_m / f.bound_m);
  }
}

void bench_aloe(const std::string& dir) {
  const cv::Mat l = cv::imread(dir + "/aloeL.jpg", cv::IMREAD_GRAYSCALE);
  const cv::Mat r = cv::imread(dir + "/aloeR.jpg", cv::IMREAD_GRAYSCALE);
  if (l.empty() || r.empty()) {
    std::printf("aloe: cannot read %s/aloeL.jpg / aloeR.jpg, skipped\n", dir.c_str());
    return;
  }
  const auto t0 = Clock::now();
  const auto matches = match_rows(l, r, RowCheckParams{});
  const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  const RowResidualStats s = summarize_rows(matches);
  const EpipolarCheck check(EpipolarParams{});
  std::size_t accepted = 0;
  for (const RowMatch& m : matches) accepted += check.check(m.left_px, m.right_px).accepted;
  std::printf(
      "aloe row check (%dx%d, 2D block matching, NCC >= 0.9, back-match): %zu matches "
      "in %.0f ms\n",
      l.cols, l.rows, s.count, ms);
  std::printf(
      "  |dy|: mean %.3f px, median %.3f px, p90 %.3f px, max %.3f px; mean dy %+.3f px; "
      "accepted by the 2 px epipolar check: %zu/%zu (%.1f %%)\n",
      s.mean_abs_px, s.median_abs_px, s.p90_abs_px, s.max_abs_px, s.mean_signed_px, accepted,
      s.count, s.count ? 100.0 * accepted / s.count : 0.0);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Stereo geometry benchmark: rectification and point-rectify time, synthetic depth "
      "accuracy vs the noise bound, epipolar row check on the real Aloe pair.",
      "stereoball-bench-stereo"};
  int iterations = 200, threads = 1, points = 5000;
  std::string data = std::string(SB_SHARED_DATA_DIR) + "/opencv-samples";
  app.add_option("--iterations", iterations, "timed rectifications per case")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--threads", threads, "OpenCV threads (0 = OpenCV default)")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  app.add_option("--points", points, "Monte Carlo points per depth")
      ->check(CLI::Range(10, 10000000))
      ->capture_default_str();
  app.add_option("--data", data, "folder with aloeL.jpg / aloeR.jpg")->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "stereoball-bench-stereo: " << e.what() << "\n";
    return 1;
  }
  if (threads > 0) cv::setNumThreads(threads);
  std::printf("OpenCV threads: %d\n", cv::getNumThreads());
  bench_rectification(iterations);
  bench_depth(points);
  bench_aloe(data);
  return 0;
}
