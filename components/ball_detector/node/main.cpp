// ball_detector: finds the ball in every stereo frame (rectification, Pixel-to-Pixel on both
// eyes, epipolar pairing, triangulation, size check; paper sections II and III) and publishes
// ball/detection. Runs until SIGINT/SIGTERM.

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "ball_detector/node/ball_detector_node.hpp"
#include "ball_detector/pipeline/detector_params_file.hpp"
#include "common/node/common_flags.hpp"
#include "common/node/node_runner.hpp"

int main(int argc, char** argv) {
  namespace sb = stereoball;
  sb::node::block_termination_signals();
  CLI::App app{
      "ball_detector: subscribes stereo/frame and stereo/calibration, rectifies both eyes,\n"
      "runs Pixel-to-Pixel on each, pairs circles on the same rectified row, triangulates,\n"
      "rejects pairs whose size does not fit the ball diameter, and publishes one\n"
      "ball/detection per frame (best pair or the reason there is none)."};
  sb::node::CommonOptions common;
  sb::node::add_common_flags(app, common, "ball_detector.yaml");
  sb::node::add_help_params(app, sb::params::specs(sb::ball_detector::detector_fields()));
  CLI11_PARSE(app, argc, argv);

  auto params = sb::ball_detector::load_detector_params(common.config_path);
  if (!params) {
    std::fprintf(stderr, "ball_detector: %s\n", params.error().c_str());
    return 2;
  }
  try {
    sb::node::Runner runner("ball_detector", common);
    sb::ball_detector::BallDetectorNode node(runner, *params);
    return runner.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ball_detector: %s\n", e.what());
    return 1;
  }
}
