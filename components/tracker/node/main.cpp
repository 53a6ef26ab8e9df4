// tracker: verifies ball detections (block matching + statistics, paper
// section IV) and publishes ball/track. Runs until SIGINT/SIGTERM.

#include "common/node/run_node.hpp"
#include "tracker/node/tracker_node.hpp"
#include "tracker/node/tracker_params_file.hpp"

namespace sb = stereoball;

int main(int argc, char** argv) {
  const char* help =
      "tracker: verifies ball/detection by block matching (SSD of 21x21 RGB blocks) and\n"
      "statistics of the last five 3D positions, and publishes ball/track (state idle /\n"
      "following / searching, accepted position and velocity, last-seen side, verdict).";
  return sb::node::run_node<sb::tracker::TrackerNode>(
      argc, argv,
      {"tracker", help, "tracker.yaml", sb::params::specs(sb::tracker::tracker_fields()), {}},
      sb::tracker::load_tracker_params);
}
