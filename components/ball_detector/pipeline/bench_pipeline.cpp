// stereoball-bench-pipeline: time per stereo frame of the ball detector pipeline (rectify both
// eyes through the LUT, Pixel-to-Pixel on both, pairing, triangulation, patch) on 640x480
// frames rendered by the simulator. Prints figures; never asserts.

#include "common/util/cli11.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <vector>

#include "ball_detector/pipeline/stereo_pipeline.hpp"
#include "common/util/bench_clock.hpp"
#include "simulator/core/ball_scene.hpp"

namespace sb = stereoball;

namespace {

using stereoball::bench::thread_cpu_ms;
using stereoball::bench::wall_ms;

struct Stats {
  double median = 0, p95 = 0, max = 0;
};

Stats stats(std::vector<double> v) {
  Stats s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.median = v[v.size() / 2];
  s.p95 = v[std::min(v.size() - 1, static_cast<size_t>(std::ceil(0.95 * v.size())) - 1)];
  s.max = v.back();
  return s;
}

void print_row(const char* what, const Stats& s) {
  std::printf("%-34s median %6.2f ms   p95 %6.2f ms   max %6.2f ms\n", what, s.median, s.p95,
              s.max);
}

// The bench's options (its command line).
struct Options {
  int frames = 60;
  int threads = 1;
  bool clutter = false;
  bool plain = false;
  std::string input = sb::ball_detector::to_string(sb::ball_detector::BallDetectorParams{}.input);
  bool full_right = false;
  double size_tolerance = sb::ball_detector::BallDetectorParams{}.size_max_relative_error;
  std::vector<int> k_values = {5};
  double min_score = sb::ball_detector::PixelToPixelParams{}.min_score;
};

void add_options(CLI::App& app, Options& o) {
  app.add_option("--frames", o.frames, "stereo frames to time")->check(CLI::Range(5, 10000));
  app.add_option("--threads", o.threads, "OpenCV threads (1 = one core, the target)")
      ->check(CLI::Range(1, 64));
  app.add_flag("--clutter", o.clutter, "boxes, door frame and a round plate in the room");
  app.add_flag("--plain", o.plain, "untextured floor and one-colour ball");
  app.add_option("--k", o.k_values, "Pixel-to-Pixel half window sizes (repeat for multi-k)")
      ->check(CLI::Range(1, 31));
  app.add_option("--min-score", o.min_score, "drop circles scoring below this")
      ->check(CLI::Range(0.0, 1.0));
  app.add_flag("--full-right", o.full_right,
               "search the whole right image (default: only the rows of left circles)");
  app.add_option("--size-tolerance", o.size_tolerance,
                 "accepted relative radius error at the triangulated depth")
      ->check(CLI::Range(0.001, 10.0));
  app.add_option(
      "--input", o.input,
      "detector input image: grey, saturation, value, red, green, blue (default: the pipeline's)");
}

// A ball rolling across and away in front of the robot (varied positions and sizes), rendered.
sb::simulator::SimBallSetup rolling_ball(const Options& o) {
  sb::simulator::SimBallSetup setup;
  setup.ball_x_m = 1.0;
  setup.ball_y_m = 0.4;
  setup.vx_mps = 0.5;
  setup.vy_mps = -0.3;
  setup.clutter = o.clutter;
  setup.plain_room = o.plain;
  setup.uniform_ball = o.plain;
  return setup;
}

// Per-frame times of the whole pipeline and of its stages run alone, ms; detection counts.
struct Figures {
  std::vector<double> total, total_wall, chroma, rectify, p2p;
  int found = 0, visible = 0, within_1px = 0;
};

Figures time_frames(sb::ball_detector::StereoPipeline& pipeline,
                    const sb::ball_detector::BallDetectorParams& params,
                    const sb::stereo::StereoCalibration& calibration,
                    const std::vector<sb::simulator::SimFrame>& rendered) {
  auto rectifier = sb::stereo::Rectifier::create(calibration).value();
  sb::ball_detector::PixelToPixelDetector detector(params.detector_params());
  pipeline.step(rendered[0].left, rendered[0].right, false);  // warm-up (first allocations)
  Figures fig;
  cv::Mat grey_l, grey_r, rect_l, rect_r;
  for (const auto& f : rendered) {
    const double w0 = wall_ms();
    double t0 = thread_cpu_ms();
    const auto det = pipeline.step(f.left, f.right, false);
    fig.total.push_back(thread_cpu_ms() - t0);
    fig.total_wall.push_back(wall_ms() - w0);

    t0 = thread_cpu_ms();
    sb::ball_detector::saturation(f.left, grey_l);
    sb::ball_detector::saturation(f.right, grey_r);
    fig.chroma.push_back(thread_cpu_ms() - t0);
    t0 = thread_cpu_ms();
    rectifier.rectify(grey_l, grey_r, rect_l, rect_r);
    fig.rectify.push_back(thread_cpu_ms() - t0);
    t0 = thread_cpu_ms();
    detector.detect(rect_l);
    fig.p2p.push_back(thread_cpu_ms() - t0);

    const bool vis = f.truth.ball_visible_left && f.truth.ball_visible_right;
    fig.visible += vis;
    if (det.status == sb::ball_detector::DetectionStatus::kFound) {
      ++fig.found;
      if (vis && std::abs(det.left.x_px - f.truth.ball_left_px.x) <= 1.0 &&
          std::abs(det.left.y_px - f.truth.ball_left_px.y) <= 1.0)
        ++fig.within_1px;
    }
  }
  return fig;
}

void print_figures(const Options& o, const Figures& fig) {
  std::printf("stereoball-bench-pipeline: %d frames 640x480, %d OpenCV thread(s), input %s, %s\n",
              o.frames, o.threads, o.input.c_str(), o.clutter ? "clutter" : "no clutter");
  std::printf("CPU time of the calling thread (wall time depends on the machine's load):\n");
  print_row("whole pipeline per stereo frame", stats(fig.total));
  print_row("  chroma (saturation), both eyes", stats(fig.chroma));
  print_row("  LUT rectify one channel, both eyes", stats(fig.rectify));
  print_row("  Pixel-to-Pixel, one eye", stats(fig.p2p));
  print_row("whole pipeline, wall clock", stats(fig.total_wall));
  std::printf("ball visible in %d frames; found in %d; left centre within 1 px of truth in %d\n",
              fig.visible, fig.found, fig.within_1px);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Times the ball detector pipeline per stereo frame (rectify + 2x Pixel-to-Pixel + pairing)\n"
      "on 640x480 frames rendered by the simulator; prints median / p95 and detection figures."};
  Options o;
  add_options(app, o);
  CLI11_PARSE(app, argc, argv);
  const auto parsed_input = sb::ball_detector::parse_detector_input(o.input);
  if (!parsed_input) {
    std::fprintf(stderr, "stereoball-bench-pipeline: unknown --input '%s'\n", o.input.c_str());
    return 2;
  }
  cv::setNumThreads(o.threads);
  const auto sim_params = sb::simulator::default_sim_params();
  const auto scenario = sb::simulator::make_sim_scenario(rolling_ball(o));
  if (auto e = sb::simulator::Simulator::check(sim_params, scenario); !e) {
    std::fprintf(stderr, "stereoball-bench-pipeline: %s\n", e.error().c_str());
    return 1;
  }
  sb::simulator::Simulator sim(sim_params, scenario);
  std::vector<sb::simulator::SimFrame> rendered;
  for (int i = 0; i < o.frames; ++i)
    rendered.push_back(sim.step(std::nullopt, static_cast<int64_t>(i) * 50'000'000));

  sb::ball_detector::BallDetectorParams params;
  params.input = *parsed_input;
  params.p2p.k_values = o.k_values;
  params.right_eye_partner_boxes = !o.full_right;
  params.size_max_relative_error = o.size_tolerance;
  params.p2p.min_score = o.min_score;
  sb::ball_detector::StereoPipeline pipeline(params);
  if (auto e = pipeline.set_calibration(sim.calibration()); !e) {
    std::fprintf(stderr, "stereoball-bench-pipeline: calibration: %s\n", e.error().c_str());
    return 1;
  }
  print_figures(o, time_frames(pipeline, params, sim.calibration(), rendered));
  return 0;
}
