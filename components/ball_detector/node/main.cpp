// ball_detector: finds the ball in every stereo frame (rectification, Pixel-to-Pixel on both
// eyes, epipolar pairing, triangulation, size check; paper sections II and III) and publishes
// ball/detection. Runs until SIGINT/SIGTERM.

#include "ball_detector/node/ball_detector_node.hpp"
#include "ball_detector/pipeline/detector_params_file.hpp"
#include "common/node/run_node.hpp"

namespace sb = stereoball;

int main(int argc, char** argv) {
  const char* help =
      "ball_detector: subscribes stereo/frame and stereo/calibration, rectifies both eyes,\n"
      "runs Pixel-to-Pixel on each, pairs circles on the same rectified row, triangulates,\n"
      "rejects pairs whose size does not fit the ball diameter, and publishes one\n"
      "ball/detection per frame (best pair or the reason there is none).";
  return sb::node::run_node<sb::ball_detector::BallDetectorNode>(
      argc, argv,
      {"ball_detector",
       help,
       "ball_detector.yaml",
       sb::params::specs(sb::ball_detector::detector_fields()),
       {}},
      sb::ball_detector::load_detector_params);
}
