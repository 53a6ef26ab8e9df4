#include "loop_config.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "ball_detector/pipeline/detector_params_file.hpp"
#include "motion_controller/node/controller_params_file.hpp"
#include "simulator/io/scenario_file.hpp"
#include "simulator/io/sim_params_file.hpp"
#include "tracker/node/tracker_params_file.hpp"

namespace stereoball::sim_loop {

Result<LoopConfig> load_loop_config(const std::string& config_dir) {
  LoopConfig c;
  auto sim = simulator::load_sim_params(config_dir + "/simulator.yaml");
  if (!sim) return Error{sim.error()};
  auto det = ball_detector::load_detector_params(config_dir + "/ball_detector.yaml");
  if (!det) return Error{det.error()};
  auto trk = tracker::load_tracker_params(config_dir + "/tracker.yaml");
  if (!trk) return Error{trk.error()};
  auto ctl = motion_controller::load_controller_params(config_dir + "/motion_controller.yaml");
  if (!ctl) return Error{ctl.error()};
  c.sim = sim.value();
  c.detector = det.value();
  c.tracker = trk.value();
  c.controller = ctl.value().controller;
  c.controller_rate_hz = ctl.value().rate_hz;
  return c;
}

std::vector<std::string> scenario_names(const std::string& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec))
    if (e.path().extension() == ".yaml") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

Result<simulator::Scenario> load_scenario(const std::string& name_or_path, const std::string& dir,
                                          bool plain) {
  auto s = simulator::load_scenario_by_name(name_or_path, dir);
  if (!s) return Error{s.error()};
  if (plain) make_plain(s.value());
  return s;
}

void make_plain(simulator::Scenario& scenario) {
  scenario.room.plain = true;
  if (scenario.ball) scenario.ball->color_b = scenario.ball->color_a;
}

Result<RunFrames> run_all(const LoopConfig& config) {
  auto loop = SimLoop::create(config);
  if (!loop) return Error{loop.error()};
  RunFrames out;
  out.frames.reserve(static_cast<std::size_t>((*loop)->frame_count()));
  while ((*loop)->frames_done() < (*loop)->frame_count()) out.frames.push_back((*loop)->step());
  return out;
}

double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double rank = std::ceil(q * static_cast<double>(values.size()));
  const auto i = static_cast<std::size_t>(std::max(1.0, rank)) - 1;
  return values[std::min(i, values.size() - 1)];
}

}  // namespace stereoball::sim_loop
