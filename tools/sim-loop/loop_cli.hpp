#pragma once
// Command-line options shared by the offline loop tools (stereoball bench tracking,
// stereoball bench closed-loop), and what they select.

#include "common/util/cli11.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "simulator/core/randomize.hpp"

#include "common/util/result.hpp"
#include "sim_loop.hpp"

namespace stereoball::sim_loop {

/// --scenario, --seconds, --plain, --config-dir, --randomize, --seed, --ranges.
struct LoopCli {
  std::vector<std::string> scenarios;  ///< names or paths; empty = every scenario file
  std::string config_dir;              ///< simulator/detector/tracker/controller YAML + scenarios/
  double seconds = -1.0;               ///< simulated seconds per run; <= 0 = scenario duration
  bool plain = false;                  ///< plain room and one-colour ball
  int randomize = 0;                   ///< > 0: that many randomised scenes instead of scenarios
  /// Randomised: the scene sets (N scenes from each, in order; default {1}); else at most one,
  /// every scenario's seed.
  std::vector<std::uint64_t> seeds;
  std::string ranges;  ///< randomised: range file (default config_dir/randomize.yaml)
};

/// Adds the shared options to app; config_dir's default is o.config_dir as given.
void add_loop_options(CLI::App& app, LoopCli& o);

/// The loaded configuration and every selected scenario (all checked before any run).
struct LoopSelection {
  LoopConfig base;
  std::vector<simulator::Scenario> scenarios;
  /// Randomised runs: each scenario's categories and ball diameter (parallel to scenarios).
  std::vector<simulator::RandomScene> random;
};

/// The configuration of run i: base with scenario i, and for a randomised scene the detector's
/// ball.diameter_m set to its ball (the only setting that changes per scene).
LoopConfig config_for(const LoopSelection& selection, std::size_t i);
/// Loads the configuration and the scenarios; the error names the file, key or scenario.
Result<LoopSelection> select_runs(const LoopCli& o);

/// Simulated seconds to run scenario: --seconds if given, else its duration_s.
double run_seconds(const LoopCli& o, const simulator::Scenario& scenario);

}  // namespace stereoball::sim_loop
