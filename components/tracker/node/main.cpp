// tracker: verifies ball detections (block matching + statistics, paper
// section IV) and publishes ball/track. Runs until SIGINT/SIGTERM.

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "common/node/common_flags.hpp"
#include "common/node/node_runner.hpp"
#include "tracker/node/tracker_node.hpp"
#include "tracker/node/tracker_params_file.hpp"

int main(int argc, char** argv) {
  namespace sb = stereoball;
  sb::node::block_termination_signals();
  CLI::App app{
      "tracker: verifies ball/detection by block matching (SSD of 21x21 RGB blocks) and\n"
      "statistics of the last five 3D positions, and publishes ball/track (state idle /\n"
      "following / searching, accepted position and velocity, last-seen side, verdict)."};
  sb::node::CommonOptions common;
  sb::node::add_common_flags(app, common, "tracker.yaml");
  sb::node::add_help_params(app, sb::params::specs(sb::tracker::tracker_fields()));
  CLI11_PARSE(app, argc, argv);

  auto params = sb::tracker::load_tracker_params(common.config_path);
  if (!params) {
    std::fprintf(stderr, "tracker: %s\n", params.error().c_str());
    return 2;
  }
  try {
    sb::node::Runner runner("tracker", common);
    sb::tracker::TrackerNode node(runner, *params);
    return runner.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tracker: %s\n", e.what());
    return 1;
  }
}
