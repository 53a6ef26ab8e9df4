// stereoball-sim: runs a simulator scenario headless (no DDS), optionally writing both raw
// eyes as PNG, the ground truth as CSV and the true calibration to --png-dir.

#include <opencv2/imgcodecs.hpp>
#include "common/util/cli11.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "common/util/cli_checks.hpp"
#include "common/util/install_layout.hpp"
#include "simulator/core/randomize.hpp"
#include "simulator/core/simulator.hpp"
#include "simulator/io/ground_truth_csv.hpp"
#include "simulator/io/randomize_file.hpp"
#include "simulator/io/scenario_file.hpp"
#include "simulator/io/sim_params_file.hpp"
#include "stereo/io/calibration_file.hpp"

namespace sim = stereoball::simulator;

namespace {

struct Options {
  std::string scenario = "ball_still";
  std::string config = stereoball::paths::shipped_config_path("simulator.yaml");
  std::string scenarios_dir = stereoball::paths::shipped_config_path("scenarios");
  double duration_s = -1.0;
  std::string png_dir;
  std::string drive = "none";
  int every = 1;
  std::optional<int> width_px, height_px;
  int randomize = 0;
  std::uint64_t seed = 1;
  std::string ranges = stereoball::paths::shipped_config_path("randomize.yaml");
  std::optional<double> eye_skew_ms;
};

// Simple pursuit on the ground truth: turn toward the ball, keep about 1 m from it.
std::optional<sim::VelocityCommand> follow(const sim::GroundTruth& g, int64_t t_ns) {
  if (!g.ball_present || !g.ball_visible_left) return sim::VelocityCommand{0.0, 0.0, t_ns};
  const double bearing = std::atan2(g.ball_camera_m.x, g.ball_camera_m.z);  // + = right
  const double dist = std::hypot(g.ball_camera_m.x, g.ball_camera_m.z);
  return sim::VelocityCommand{std::clamp(0.8 * (dist - 1.0), 0.0, 0.6), -1.5 * bearing, t_ns};
}

std::optional<sim::VelocityCommand> command_for(const Options& o, const sim::Scenario& s,
                                                const std::optional<sim::GroundTruth>& last,
                                                int64_t t_ns) {
  if (o.drive == "script") {
    const auto c = sim::scripted_command_at(s, t_ns * 1e-9);
    if (!c) return std::nullopt;
    return sim::VelocityCommand{c->linear_mps, c->angular_radps, t_ns};
  }
  if (o.drive == "follow" && last) return follow(*last, t_ns);
  return std::nullopt;
}

int fail(const std::string& message) {
  std::fprintf(stderr, "stereoball-sim: %s\n", message.c_str());
  return 2;
}

std::string frame_name(const std::string& dir, const char* eye, uint64_t seq) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%s_%06llu.png", eye, static_cast<unsigned long long>(seq));
  return (std::filesystem::path(dir) / buf).string();
}

int run_scenario(const Options& o, const sim::SimParams& params, const sim::Scenario& scenario,
                 const std::string& png_dir) {
  if (auto e = sim::Simulator::check(params, scenario); !e) return fail(e.error());

  std::ofstream csv, frames_csv;
  if (!png_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(png_dir, ec);
    if (ec) return fail("--png-dir " + png_dir + ": " + ec.message());
    csv.open(std::filesystem::path(png_dir) / "ground_truth.csv");
    if (!csv) return fail("--png-dir " + png_dir + ": cannot write ground_truth.csv");
    csv << sim::ground_truth_csv_header() << "\n";
    if (scenario.calibration) {
      frames_csv.open(std::filesystem::path(png_dir) / "frames.csv");
      if (!frames_csv) return fail("--png-dir " + png_dir + ": cannot write frames.csv");
      frames_csv << "left,right,left_stamp_ns,right_stamp_ns,left_hold,right_hold\n";
    }
  }

  sim::Simulator simulator(params, scenario);
  if (!png_dir.empty()) {
    const auto path = (std::filesystem::path(png_dir) / "calibration.yaml").string();
    stereoball::stereo::CalibrationFileInfo info;
    info.note = "true calibration of the simulated rig (stereoball-sim)";
    if (auto e = stereoball::stereo::save_calibration(path, simulator.calibration(), info); !e) {
      return fail(e.error());
    }
  }
  const double duration_s = o.duration_s > 0 ? o.duration_s : scenario.duration_s;
  const int64_t period_ns = simulator.frame_period_ns();
  const auto frames = static_cast<int64_t>(std::floor(duration_s * 1e9 / period_ns)) + 1;
  std::optional<sim::GroundTruth> last;
  int visible = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int64_t i = 0; i < frames; ++i) {
    const int64_t t_ns = i * period_ns;
    const sim::SimFrame f = simulator.step(command_for(o, scenario, last, t_ns), t_ns);
    last = f.truth;
    visible += f.truth.ball_visible_left ? 1 : 0;
    if (png_dir.empty()) continue;
    csv << sim::ground_truth_csv_row(f.truth) << "\n";
    if (i % o.every != 0) continue;
    if (!cv::imwrite(frame_name(png_dir, "left", f.seq), f.left) ||
        !cv::imwrite(frame_name(png_dir, "right", f.seq), f.right)) {
      return fail("--png-dir " + png_dir + ": cannot write PNG files");
    }
    if (f.board) {
      // Each eye's capture stamp: what `stereoball calibrate --sequence` needs for free-running
      // eyes; the hold index (-1 while the board moves) is the truth, for checking.
      frames_csv << std::filesystem::path(frame_name(png_dir, "left", f.seq)).filename().string()
                 << ","
                 << std::filesystem::path(frame_name(png_dir, "right", f.seq)).filename().string()
                 << "," << f.sim_time_ns << "," << f.right_time_ns << "," << f.board->left_hold
                 << "," << f.board->right_hold << "\n";
    }
  }
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto& r = simulator.world().robot();
  std::printf(
      "scenario %s: %lld frames (%dx%d, %.1f s simulated) in %.2f s wall; ball visible (left) in "
      "%d frames; robot at (%.2f, %.2f) m, yaw %.2f rad%s%s\n",
      scenario.name.c_str(), static_cast<long long>(frames), params.width_px, params.height_px,
      duration_s, wall_s, visible, r.x_m, r.y_m, r.yaw_rad, png_dir.empty() ? "" : "; wrote ",
      png_dir.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "stereoball-sim: run a simulator scenario headless (no DDS). Renders both raw (distorted)\n"
      "camera images of the simulated stereo rig and the ground truth for every frame; with\n"
      "--png-dir writes left_NNNNNN.png, right_NNNNNN.png, ground_truth.csv and calibration.yaml\n"
      "(the true calibration of the simulated rig); calibration scenes (e.g. --scenario\n"
      "calibration_board) also write frames.csv (each eye's capture stamp) for\n"
      "`stereoball calibrate --sequence DIR/frames.csv`."};
  Options o;
  app.add_option("--scenario", o.scenario,
                 "scenario name (config/scenarios/NAME.yaml) or path to a scenario file")
      ->capture_default_str();
  app.add_option("--config", o.config, "simulator params file")->capture_default_str();
  app.add_option("--scenarios-dir", o.scenarios_dir, "where scenario names are looked up")
      ->capture_default_str();
  app.add_option("--duration", o.duration_s, "simulated seconds (default: the scenario's)")
      ->check(CLI::PositiveNumber);
  app.add_option("--png-dir", o.png_dir,
                 "write frames, ground_truth.csv and calibration.yaml here");
  app.add_option("--drive", o.drive,
                 "robot commands: none (stand still), script (the scenario's commands list), "
                 "follow (pursue the ball using the ground truth)")
      ->check(CLI::IsMember({"none", "script", "follow"}))
      ->capture_default_str();
  app.add_option("--every", o.every, "write only every Nth frame as PNG")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--randomize", o.randomize,
                 "run N randomised scenes (ranges from --ranges) instead of --scenario; with "
                 "--png-dir each scene goes to its own subfolder")
      ->check(CLI::Range(1, 100000));
  app.add_option("--seed", o.seed,
                 "with --randomize: which scene set; with a calibration scene's random_poses: "
                 "which pose set")
      ->check(stereoball::cli::unsigned_64())
      ->capture_default_str();
  app.add_option("--ranges", o.ranges, "with --randomize: range file")->capture_default_str();
  app.add_option("--eye-skew-ms", o.eye_skew_ms,
                 "calibration scenes: the right eye captures this many ms after the left "
                 "(free-running eyes; overrides the scenario's eye_skew_ms)")
      ->check(CLI::Range(-1000.0, 1000.0));
  app.add_option("--width", o.width_px, "override image width, pixels");
  app.add_option("--height", o.height_px, "override image height, pixels");
  CLI11_PARSE(app, argc, argv);

  auto params = sim::load_sim_params(o.config);
  if (!params) return fail(params.error());
  if (o.width_px) params->width_px = *o.width_px;
  if (o.height_px) params->height_px = *o.height_px;
  if (o.randomize == 0) {
    auto scenario = sim::load_scenario_by_name(o.scenario, o.scenarios_dir);
    if (!scenario) return fail(scenario.error());
    if (o.eye_skew_ms) {
      if (!scenario->calibration)
        return fail("--eye-skew-ms: scenario '" + scenario->name +
                    "' is not a calibration scene (no calibration: section)");
      scenario->calibration->eye_skew_s = *o.eye_skew_ms * 1e-3;
    }
    // A calibration scene's drawn poses: --seed picks another pose set.
    if (app.count("--seed") > 0 && scenario->calibration && scenario->calibration->random_poses)
      scenario->calibration->random_poses->seed = o.seed;
    return run_scenario(o, *params, *scenario, o.png_dir);
  }
  auto ranges = sim::load_randomize_ranges(o.ranges);
  if (!ranges) return fail(ranges.error());
  for (const sim::RandomScene& scene : sim::draw_scenes(*ranges, o.seed, o.randomize)) {
    const auto& l = scene.labels;
    std::printf(
        "%s: ball %.3f m %s %s, floor %s, contrast %s (dE %.0f), distractors %s, leave %s\n",
        scene.scenario.name.c_str(), scene.ball_diameter_m, l.ball_colour.c_str(),
        l.pattern.c_str(), l.floor.c_str(), l.contrast.c_str(), l.contrast_delta_e,
        l.distractors.c_str(), l.leave_view.c_str());
    const std::string dir =
        o.png_dir.empty() ? "" : (std::filesystem::path(o.png_dir) / scene.scenario.name).string();
    if (const int rc = run_scenario(o, *params, scene.scenario, dir)) return rc;
  }
  return 0;
}
