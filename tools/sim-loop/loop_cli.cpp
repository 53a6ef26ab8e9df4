#include "loop_cli.hpp"

#include "loop_config.hpp"

namespace stereoball::sim_loop {

void add_loop_options(CLI::App& app, LoopCli& o) {
  app.add_option("--scenario", o.scenarios,
                 "scenario name (config/scenarios/NAME.yaml) or path; repeat; default: all");
  app.add_option("--seconds", o.seconds,
                 "simulated seconds per run (default: each scenario's duration_s)")
      ->check(CLI::Range(0.1, 3600.0));
  app.add_flag("--plain", o.plain,
               "untextured floor and one-colour ball in every scenario (the detector's easy "
               "case: separates the rest of the loop from detector misses)");
  app.add_option("--config-dir", o.config_dir,
                 "folder with simulator.yaml, ball_detector.yaml, tracker.yaml, "
                 "motion_controller.yaml and scenarios/")
      ->capture_default_str();
}

Result<LoopSelection> select_runs(const LoopCli& o) {
  auto loaded = load_loop_config(o.config_dir);
  if (!loaded) return Error{loaded.error()};
  LoopSelection out{loaded.value(), {}};
  const std::string dir = o.config_dir + "/scenarios";
  std::vector<std::string> names = o.scenarios;
  if (names.empty()) names = scenario_names(dir);
  if (names.empty()) return Error{"no scenario files (*.yaml) in " + dir};
  for (const auto& name : names) {
    auto s = load_scenario(name, dir, o.plain);
    if (!s) return Error{s.error()};
    out.scenarios.push_back(s.value());
  }
  return out;
}

double run_seconds(const LoopCli& o, const simulator::Scenario& scenario) {
  return o.seconds > 0 ? o.seconds : scenario.duration_s;
}

}  // namespace stereoball::sim_loop
