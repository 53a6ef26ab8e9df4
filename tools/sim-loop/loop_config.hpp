#pragma once
// Loading a loop configuration from a config folder, choosing scenarios, the plain variant.

#include <string>
#include <vector>

#include "common/util/result.hpp"
#include "sim_loop.hpp"

namespace stereoball::sim_loop {

/// Reads simulator.yaml, ball_detector.yaml, tracker.yaml and motion_controller.yaml from
/// config_dir (the scenario is left at its default); errors name the file and key.
Result<LoopConfig> load_loop_config(const std::string& config_dir);

/// Names (file stems) of the *.yaml files in dir, sorted; empty if there are none.
std::vector<std::string> scenario_names(const std::string& dir);

/// Loads the scenario NAME (dir/NAME.yaml) or a path, with --plain applied if plain is set.
Result<simulator::Scenario> load_scenario(const std::string& name_or_path, const std::string& dir,
                                          bool plain);

/// Untextured floor and a one-colour ball (the detector's easy case).
void make_plain(simulator::Scenario& scenario);

/// Every frame of a run, or the error that stopped it (run_all).
struct RunFrames {
  std::vector<LoopFrame> frames;
};
/// Runs the loop to the end and returns every frame, or an error naming the problem.
Result<RunFrames> run_all(const LoopConfig& config);

/// Nearest-rank quantile (q = 0.5 median, 0.95 p95) of a copy of values; 0 when empty.
double percentile(std::vector<double> values, double q);

}  // namespace stereoball::sim_loop
