// stereoball-sim-bench: measures the simulator's render time per stereo pair (both eyes) and,
// with --frame-encoding jpeg|png, the encode time and bytes of a compressed pair (the node's
// encoder).

#include "common/util/bench_clock.hpp"
#include "common/util/install_layout.hpp"

#include "common/util/cli11.hpp"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "simulator/core/simulator.hpp"
#include "simulator/io/scenario_file.hpp"
#include "simulator/io/sim_params_file.hpp"

namespace sim = stereoball::simulator;
namespace paths = stereoball::paths;
using Clock = std::chrono::steady_clock;

namespace {

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double cpu_ms() {
  return stereoball::bench::thread_cpu_ms();
}

void report(const char* what, std::vector<double> ms) {
  std::sort(ms.begin(), ms.end());
  const auto at = [&](double q) { return ms[static_cast<size_t>(q * (ms.size() - 1))]; };
  std::printf("  %-34s median %6.2f ms  p10 %6.2f  p90 %6.2f  max %6.2f  (%zu frames)\n", what,
              at(0.5), at(0.1), at(0.9), ms.back(), ms.size());
}

// Bytes of one raw bgr8 eye.
double raw_bytes_per_eye(const sim::SimParams& p) {
  return 3.0 * p.width_px * p.height_px;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "stereoball-sim-bench: time the simulator per stereo pair (both eyes) on one core.\n"
      "Reports render-only time and the full step (render + sensor noise + ground truth)."};
  std::string scenario_name = "ball_rolling_across";
  std::string config = paths::shipped_config_path("simulator.yaml");
  int frames = 300, width = 0, height = 0, blur = 0;
  app.add_option("--scenario", scenario_name, "scenario name or path")->capture_default_str();
  app.add_option("--config", config, "simulator params file")->capture_default_str();
  app.add_option("--frames", frames, "frames to time")
      ->check(CLI::Range(10, 100000))
      ->capture_default_str();
  app.add_option("--width", width, "override image width, pixels");
  app.add_option("--height", height, "override image height, pixels");
  app.add_option("--blur", blur, "override motion blur sub-frames")->check(CLI::Range(1, 16));
  stereoball::stereo::FrameCodecParams codec;
  app.add_option("--frame-encoding", codec.frame_encoding,
                 "also time compressing each pair: raw (no), jpeg or png")
      ->check(CLI::IsMember(stereoball::stereo::frame_encoding_choices()))
      ->capture_default_str();
  app.add_option("--jpeg-quality", codec.jpeg_quality, "JPEG quality")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  auto params = sim::load_sim_params(config);
  if (!params) return std::fprintf(stderr, "stereoball-sim-bench: %s\n", params.error().c_str()), 2;
  if (width > 0) params->width_px = width;
  if (height > 0) params->height_px = height;
  if (blur > 0) params->sensor.motion_blur_subframes = blur;
  auto scenario =
      sim::load_scenario_by_name(scenario_name, paths::shipped_config_path("scenarios"));
  if (!scenario)
    return std::fprintf(stderr, "stereoball-sim-bench: %s\n", scenario.error().c_str()), 2;
  if (auto e = sim::Simulator::check(*params, *scenario); !e) {
    return std::fprintf(stderr, "stereoball-sim-bench: %s\n", e.error().c_str()), 2;
  }

  const auto t_build = Clock::now();
  sim::Simulator simulator(*params, *scenario);
  const double build_ms = ms_since(t_build);
  sim::Renderer renderer(simulator.rig(), *scenario, params->left.gain, params->right.gain);
  sim::World world(*params, *scenario);
  const int64_t period = simulator.frame_period_ns();

  std::vector<double> render_ms, step_ms, render_cpu_ms, step_cpu_ms, encode_ms, encode_cpu_ms;
  std::vector<double> pair_bytes;
  std::optional<stereoball::stereo::EyeEncoder> encoder;
  if (codec.compressed()) encoder.emplace(codec);
  cv::Mat left, right;
  for (int i = 0; i < frames; ++i) {
    const int64_t t = i * period;
    world.set_command({0.2, 0.3, t});
    world.advance_to(t);
    const sim::LightKey light = sim::lighting_at(*scenario, t * 1e-9);
    const auto t0 = Clock::now();
    const double c0 = cpu_ms();
    renderer.render(sim::Eye::kLeft, world.robot(), world.ball(), light, left);
    renderer.render(sim::Eye::kRight, world.robot(), world.ball(), light, right);
    render_cpu_ms.push_back(cpu_ms() - c0);
    render_ms.push_back(ms_since(t0));
    const auto t1 = Clock::now();
    const double c1 = cpu_ms();
    const sim::SimFrame f = simulator.step(sim::VelocityCommand{0.2, 0.3, t}, t);
    step_cpu_ms.push_back(cpu_ms() - c1);
    step_ms.push_back(ms_since(t1));
    if (!encoder) continue;
    const auto t2 = Clock::now();
    const double c2 = cpu_ms();
    size_t bytes = 0;
    for (const cv::Mat* eye : {&f.left, &f.right}) {
      if (auto st = encoder->encode(*eye); !st) {
        return std::fprintf(stderr, "stereoball-sim-bench: %s\n", st.error().c_str()), 1;
      }
      bytes += encoder->bytes().size();
    }
    encode_cpu_ms.push_back(cpu_ms() - c2);
    encode_ms.push_back(ms_since(t2));
    pair_bytes.push_back(static_cast<double>(bytes));
  }
  std::printf("stereoball-sim-bench: scenario %s, %dx%d, blur %d, setup (ray tables) %.1f ms\n",
              scenario->name.c_str(), params->width_px, params->height_px,
              params->sensor.motion_blur_subframes, build_ms);
  report("render both eyes, wall", render_ms);
  report("render both eyes, thread CPU", render_cpu_ms);
  report("full step (+noise+truth), wall", step_ms);
  report("full step (+noise+truth), CPU", step_cpu_ms);
  if (!encoder) return 0;
  const std::string name = codec.frame_encoding == "jpeg"
                               ? "jpeg q" + std::to_string(codec.jpeg_quality)
                               : codec.frame_encoding;
  report((name + " encode both eyes, wall").c_str(), encode_ms);
  report((name + " encode both eyes, CPU").c_str(), encode_cpu_ms);
  std::sort(pair_bytes.begin(), pair_bytes.end());
  const double raw_bytes = 2.0 * raw_bytes_per_eye(*params);
  std::printf(
      "  %s bytes per pair: median %.0f (min %.0f, max %.0f) vs raw bgr8 %.0f = %.1fx "
      "smaller\n",
      name.c_str(), pair_bytes[pair_bytes.size() / 2], pair_bytes.front(), pair_bytes.back(),
      raw_bytes, raw_bytes / pair_bytes[pair_bytes.size() / 2]);
  return 0;
}
