// motion_controller: turns ball/track into cmd/velocity (follow, search, stop)
// as each new track arrives (and at a minimum rate). Runs until SIGINT/SIGTERM.

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "common/node/common_flags.hpp"
#include "common/node/node_runner.hpp"
#include "motion_controller/node/controller_params_file.hpp"
#include "motion_controller/node/motion_controller_node.hpp"

int main(int argc, char** argv) {
  namespace sb = stereoball;
  sb::node::block_termination_signals();
  CLI::App app{
      "motion_controller: subscribes ball/track and cmd/estop, publishes cmd/velocity: one\n"
      "command per new track as soon as it arrives (carrying its capture_stamp_ns), and at\n"
      "least rate_hz (default 20 Hz) without tracks: follows the ball at the target distance,\n"
      "rotates toward the last-seen side while searching, and commands zero on start-up, stale\n"
      "ball/track (stale_timeout_ns) and a latched emergency stop. Tracks with a zero, future\n"
      "or backwards capture stamp are logged and never acted on."};
  sb::node::CommonOptions common;
  sb::node::add_common_flags(app, common, "motion_controller.yaml");
  sb::node::add_help_params(app, sb::params::specs(sb::motion_controller::node_params_fields()));
  CLI11_PARSE(app, argc, argv);

  auto params = sb::motion_controller::load_controller_params(common.config_path);
  if (!params) {
    std::fprintf(stderr, "motion_controller: %s\n", params.error().c_str());
    return 2;
  }
  try {
    sb::node::Runner runner("motion_controller", common);
    sb::motion_controller::MotionControllerNode node(runner, *params);
    return runner.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "motion_controller: %s\n", e.what());
    return 1;
  }
}
