#include "loop_cli.hpp"

#include "common/util/cli_checks.hpp"
#include "loop_config.hpp"
#include "simulator/io/randomize_file.hpp"

#include <set>

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
  app.add_option("--randomize", o.randomize,
                 "run N randomised scenes (ranges from --ranges) instead of the scenario files; "
                 "the detector gets only each scene's ball diameter")
      ->check(CLI::Range(1, 100000));
  app.add_option("--seed", o.seeds,
                 "with --randomize: the scene set (default 1; repeat for several, N scenes from "
                 "each, reported together); otherwise: override every scenario's seed (sensor "
                 "noise)")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->check(cli::unsigned_64());
  app.add_option("--ranges", o.ranges,
                 "with --randomize: range file (default CONFIG_DIR/randomize.yaml)");
}

LoopConfig config_for(const LoopSelection& selection, std::size_t i) {
  LoopConfig c = selection.base;
  c.scenario = selection.scenarios.at(i);
  if (i < selection.random.size()) c.detector.ball_diameter_m = selection.random[i].ball_diameter_m;
  return c;
}

namespace {

Result<LoopSelection> select_random(const LoopCli& o, LoopSelection out) {
  if (!o.scenarios.empty()) return Error{"--randomize and --scenario exclude each other"};
  auto ranges = simulator::load_randomize_ranges(o.ranges.empty() ? o.config_dir + "/randomize.yaml"
                                                                  : o.ranges);
  if (!ranges) return Error{ranges.error()};
  const std::vector<std::uint64_t> seeds =
      o.seeds.empty() ? std::vector<std::uint64_t>{1} : o.seeds;
  std::set<std::uint64_t> seen;
  for (const std::uint64_t seed : seeds)
    if (!seen.insert(seed).second)
      return Error{"--seed " + std::to_string(seed) + " is given twice"};
  for (const std::uint64_t seed : seeds)
    for (auto& scene : simulator::draw_scenes(ranges.value(), seed, o.randomize)) {
      if (o.plain) make_plain(scene.scenario);
      out.scenarios.push_back(scene.scenario);
      out.random.push_back(std::move(scene));
    }
  return out;
}

}  // namespace

Result<LoopSelection> select_runs(const LoopCli& o) {
  auto loaded = load_loop_config(o.config_dir);
  if (!loaded) return Error{loaded.error()};
  LoopSelection out{loaded.value(), {}, {}};
  if (o.randomize > 0) return select_random(o, std::move(out));
  if (!o.ranges.empty()) return Error{"--ranges needs --randomize N"};
  if (o.seeds.size() > 1) return Error{"--seed more than once needs --randomize N"};
  const std::string dir = o.config_dir + "/scenarios";
  std::vector<std::string> names = o.scenarios;
  if (names.empty()) names = scenario_names(dir);
  if (names.empty()) return Error{"no scenario files (*.yaml) in " + dir};
  for (const auto& name : names) {
    auto s = load_scenario(name, dir, o.plain);
    if (!s) return Error{s.error()};
    if (!o.seeds.empty()) s->seed = o.seeds.front();
    out.scenarios.push_back(s.value());
  }
  return out;
}

double run_seconds(const LoopCli& o, const simulator::Scenario& scenario) {
  return o.seconds > 0 ? o.seconds : scenario.duration_s;
}

}  // namespace stereoball::sim_loop
