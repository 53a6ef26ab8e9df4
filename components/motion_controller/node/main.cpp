// motion_controller: turns ball/track into cmd/velocity (follow, search, stop)
// as each new track arrives (and at a minimum rate). Runs until SIGINT/SIGTERM.

#include "common/node/run_node.hpp"
#include "motion_controller/node/controller_params_file.hpp"
#include "motion_controller/node/motion_controller_node.hpp"

namespace sb = stereoball;

int main(int argc, char** argv) {
  const char* help =
      "motion_controller: subscribes ball/track and cmd/estop, publishes cmd/velocity: one\n"
      "command per new track as soon as it arrives (carrying its capture_stamp_ns), and at\n"
      "least rate_hz (default 20 Hz) without tracks: follows the ball at the target distance,\n"
      "rotates toward the last-seen side while searching, and commands zero on start-up, stale\n"
      "ball/track (stale_timeout_ns) and a latched emergency stop. Tracks with a zero, future\n"
      "or backwards capture stamp are logged and never acted on.";
  return sb::node::run_node<sb::motion_controller::MotionControllerNode>(
      argc, argv,
      {"motion_controller",
       help,
       "motion_controller.yaml",
       sb::params::specs(sb::motion_controller::node_params_fields()),
       {}},
      sb::motion_controller::load_controller_params);
}
