// stereoball-bench-closed-loop: the closed-loop acceptance figures of issue 7. Runs every
// scenario (several seeds) through the whole system in one process at simulated time
// (simulator core -> ball detector pipeline -> tracker core -> motion controller core at its
// rate -> simulated base) and prints, per scenario and in total: (a) how long the robot keeps
// a reachable ball within tolerance, (b) whether it turns the right way and reacquires a ball
// that left the view, (c) whether it ever follows for long with no ball. Figures only.

#include <opencv2/core.hpp>
#include "common/util/cli11.hpp"

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "closed_loop_run.hpp"
#include "common/util/install_layout.hpp"
#include "loop_cli.hpp"
#include "report.hpp"
#include "run_each.hpp"
#include "simulator/core/randomize.hpp"

namespace bc = stereoball::bench_closed_loop;
namespace sl = stereoball::sim_loop;

namespace {

struct Options {
  sl::LoopCli loop;
  int seeds = 3;
  int jobs = 1;
  std::string json_path;
  std::string trace_dir;
  double settle_s = 2.0;
  double reacquire_limit_s = 10.0;
};

int fail(const std::string& message) {
  std::fprintf(stderr, "stereoball-bench-closed-loop: %s\n", message.c_str());
  return 2;
}

void add_options(CLI::App& app, Options& o) {
  o.loop.config_dir = stereoball::paths::shipped_config_dir();
  sl::add_loop_options(app, o.loop);
  app.add_option("--seeds", o.seeds, "runs per scenario; run i uses the scenario's seed + i")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  app.add_option("--jobs", o.jobs,
                 "runs at once, each on a thread of its own (the same figures as one at a time)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  app.add_option("--json", o.json_path, "also write every figure as JSON to this file");
  app.add_option("--trace", o.trace_dir,
                 "write every run frame by frame to DIR/<scenario>_seed<N>.csv (existing folder)")
      ->check(CLI::ExistingDirectory);
  app.add_option("--settle", o.settle_s,
                 "(a): seconds the ball must be visible and slow enough before it counts as "
                 "reachable")
      ->check(CLI::Range(0.0, 60.0))
      ->capture_default_str();
  app.add_option("--reacquire-limit", o.reacquire_limit_s,
                 "(b): seconds after leaving the view within which the ball must be followed "
                 "again")
      ->check(CLI::Range(0.5, 600.0))
      ->capture_default_str();
}

bc::AcceptanceParams acceptance_params(const sl::LoopConfig& base, const Options& o) {
  bc::AcceptanceParams p;
  p.target_distance_m = base.controller.target_distance_m;
  p.max_ball_speed_mps = base.controller.max_linear_mps;
  p.search_turn_radps = 0.5 * base.controller.search_angular_radps;
  p.settle_s = o.settle_s;
  p.reacquire_limit_s = o.reacquire_limit_s;
  p.frame_period_s = 1.0 / base.sim.frame_rate_hz;
  return p;
}

// The randomised scenes' runs grouped by each category's values, one table per category.
void print_categories(const std::vector<stereoball::simulator::RandomScene>& scenes,
                      const std::vector<bc::JudgedRun>& runs, const bc::AcceptanceParams& params) {
  namespace sim = stereoball::simulator;
  std::map<std::string, const sim::SceneLabels*> labels;
  for (const auto& s : scenes) labels[s.scenario.name] = &s.labels;
  std::vector<const bc::JudgedRun*> all;
  for (const auto& r : runs) all.push_back(&r);
  const bc::Summary total = bc::summarize("TOTAL", all, params);
  for (std::size_t c = 0; c < sim::kCategoryNames.size(); ++c) {
    std::map<std::string, std::vector<const bc::JudgedRun*>> groups;
    for (const auto& r : runs) groups[sim::category_value(*labels.at(r.scenario), c)].push_back(&r);
    std::vector<bc::Summary> rows;
    for (const auto& [value, group] : groups) rows.push_back(bc::summarize(value, group, params));
    bc::print_table(stdout, rows, total, sim::kCategoryNames[c]);
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "stereoball-bench-closed-loop: closed-loop acceptance benchmark (issue 7).\n"
      "Runs each scenario with several seeds through simulator core, ball detector pipeline,\n"
      "tracker core and motion controller core (20 Hz, driving the simulated robot) in one\n"
      "process at simulated time, and prints per scenario and in total: (a) time the robot keeps\n"
      "a reachable ball within 0.25 m of the target distance and 5 deg of its heading, (b) right\n"
      "turn and reacquisition after the ball leaves the view, (c) longest 'following' with no\n"
      "ball. Figures only (exit 0); the definitions are printed with the table."};
  Options o;
  add_options(app, o);
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help
  } catch (const CLI::ParseError& e) {
    return fail(std::string(e.what()) + " (see --help)");
  }
  cv::setNumThreads(1);

  auto selected = sl::select_runs(o.loop);
  if (!selected) return fail(selected.error());
  const sl::LoopConfig& base = selected->base;
  const auto& scenarios = selected->scenarios;
  std::ofstream json_out;
  if (!o.json_path.empty()) {
    json_out.open(o.json_path);
    if (!json_out) return fail("cannot write --json file " + o.json_path);
  }
  const bc::AcceptanceParams params = acceptance_params(base, o);

  std::printf(
      "stereoball-bench-closed-loop: %zu scenario(s) x %d seed(s), camera %.0f Hz, controller "
      "%.0f Hz, target %.2f m%s\n",
      scenarios.size(), o.seeds, base.sim.frame_rate_hz, base.controller_rate_hz,
      base.controller.target_distance_m, o.loop.plain ? ", plain room and one-colour ball" : "");
  // Run k is scenario k / seeds with its seed + k % seeds.
  std::vector<bc::JudgedRun> runs(scenarios.size() * static_cast<std::size_t>(o.seeds));
  const auto status = sl::run_each(runs.size(), o.jobs, [&](std::size_t k) -> stereoball::Status {
    const std::size_t si = k / static_cast<std::size_t>(o.seeds);
    const auto& scenario = scenarios[si];
    sl::LoopConfig config = sl::config_for(*selected, si);
    config.scenario.seed = scenario.seed + k % static_cast<std::size_t>(o.seeds);
    config.seconds = sl::run_seconds(o.loop, scenario);
    const auto t0 = std::chrono::steady_clock::now();
    auto samples = bc::run_closed_loop(config);
    if (!samples) return stereoball::Error{samples.error()};
    if (!o.trace_dir.empty()) {
      const std::string path = o.trace_dir + "/" + scenario.name + "_seed" +
                               std::to_string(config.scenario.seed) + ".csv";
      std::FILE* f = std::fopen(path.c_str(), "w");
      if (!f) return stereoball::Error{"cannot write trace file " + path};
      bc::write_trace(f, samples.value());
      // A full disk or a vanished folder shows at the flush: the figures must not rest on a
      // silently cut trace.
      const bool written = std::fflush(f) == 0 && !std::ferror(f);
      if (std::fclose(f) != 0 || !written)
        return stereoball::Error{"writing trace file " + path + " failed: " + std::strerror(errno)};
    }
    bc::JudgedRun& r = runs[k];
    r = bc::JudgedRun{scenario.name, config.scenario.seed, samples->size(),
                      bc::judge_run(scenario.name, samples.value(), params)};
    std::fprintf(stderr, "  %s seed %llu: %zu frames in %.1f s\n", scenario.name.c_str(),
                 static_cast<unsigned long long>(r.seed), r.frames,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    return {};
  });
  if (!status) return fail(status.error());
  std::vector<bc::Summary> summaries;
  std::vector<const bc::JudgedRun*> all;
  for (const auto& scenario : scenarios) {
    std::vector<const bc::JudgedRun*> group;
    for (const auto& r : runs)
      if (r.scenario == scenario.name) group.push_back(&r);
    summaries.push_back(bc::summarize(scenario.name, group, params));
  }
  for (const auto& r : runs) all.push_back(&r);
  const bc::Summary total = bc::summarize("TOTAL", all, params);
  bc::print_report(stdout, summaries, total, params);
  bc::print_details(stdout, summaries, runs);
  if (!selected->random.empty()) print_categories(selected->random, runs, params);
  if (json_out.is_open()) {
    json_out << bc::to_json(runs, summaries, total, params).dump(2) << "\n";
    if (!json_out) return fail("writing --json file " + o.json_path + " failed");
  }
  return 0;
}
