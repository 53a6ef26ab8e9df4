// ball_detector: finds the ball in every stereo frame (rectification, Pixel-to-Pixel on both
// eyes, epipolar pairing, triangulation, size check; paper sections II and III) and publishes
// ball/detection. Runs until SIGINT/SIGTERM.

#include <fstream>
#include <string>

#include "ball_detector/node/ball_detector_node.hpp"
#include "ball_detector/pipeline/detector_params_file.hpp"
#include "common/node/run_node.hpp"
#include "common/util/cli11.hpp"

namespace sb = stereoball;

namespace {

// The parameters and the node's own flag.
struct Config {
  sb::ball_detector::BallDetectorParams params;
  std::string frame_times_path;
  bool pin_threads = true;
};

}  // namespace

int main(int argc, char** argv) {
  const char* help =
      "ball_detector: subscribes stereo/frame and stereo/calibration, rectifies both eyes,\n"
      "runs Pixel-to-Pixel on each, pairs circles on the same rectified row, triangulates,\n"
      "rejects pairs whose size does not fit the ball diameter, and publishes one\n"
      "ball/detection per frame (best pair or the reason there is none).";
  std::string frame_times_path;
  bool no_pin_threads = false;
  const auto add_flags = [&frame_times_path, &no_pin_threads](CLI::App& app) {
    app.add_option("--frame-times", frame_times_path,
                   "write each frame's stage times (wait, decode, the shared tasks, searches, "
                   "each thread's CPU and run-queue wait) to this CSV file, for finding slow "
                   "frames");
    app.add_flag("--no-pin-threads", no_pin_threads,
                 "leave the frame thread and the task helper to the scheduler instead of one "
                 "on each of the first two CPUs this process may use (taskset or systemd's "
                 "CPUAffinity= choose which)");
  };
  const auto load = [&frame_times_path,
                     &no_pin_threads](const sb::node::CommonOptions& common) -> sb::Result<Config> {
    auto params = sb::ball_detector::load_detector_params(common.config_path);
    if (!params) return sb::Error{params.error()};
    if (!frame_times_path.empty() && !std::ofstream(frame_times_path, std::ios::app))
      return sb::Error{"--frame-times " + frame_times_path + ": cannot write to this file"};
    return Config{std::move(params).value(), frame_times_path, !no_pin_threads};
  };
  const auto build = [](sb::node::Runner& runner, const Config& config) {
    return sb::node::NodeHandle(std::make_shared<sb::ball_detector::BallDetectorNode>(
        runner, config.params, config.frame_times_path, config.pin_threads));
  };
  return sb::node::run_node(argc, argv,
                            {"ball_detector", help, "ball_detector.yaml",
                             sb::params::specs(sb::ball_detector::detector_fields()), add_flags},
                            load, build);
}
