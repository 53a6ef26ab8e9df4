// camera_server: two V4L2 cameras (or image files) -> stereo/frame + stereo/calibration.

#include <CLI/CLI.hpp>
#include <cstdio>

#include "camera_server/node/camera_server_node.hpp"
#include "camera_server/node/camera_server_params_file.hpp"
#include "common/node/node_runner.hpp"
#include "common/util/log.hpp"
#include "stereo/frame/frame_codec_flags.hpp"

namespace sb = stereoball;

int main(int argc, char** argv) {
  sb::node::block_termination_signals();
  CLI::App app{
      "camera_server: captures two V4L2 cameras (or plays left/right image files), pairs the "
      "frames by capture stamp and publishes stereo/frame; publishes the calibration file on "
      "stereo/calibration (transient-local). Parameters: components/camera_server/README.md."};
  sb::node::CommonOptions common;
  sb::node::add_common_flags(app, common, "camera_server.yaml");
  sb::node::add_help_params(app, sb::params::specs(sb::camera_server::camera_server_fields()));
  const sb::stereo::FrameCodecFlags codec_flags(app);
  CLI11_PARSE(app, argc, argv);
  sb::log::Level level = sb::log::Level::kInfo;
  sb::log::parse_level(common.log_level, level);
  sb::log::init("camera_server", level);
  auto params = sb::camera_server::load_camera_server_params(common.config_path);
  if (!params) {
    std::fprintf(stderr, "camera_server: %s\n", params.error().c_str());
    return 2;
  }
  codec_flags.apply(params->output);
  try {
    sb::node::Runner runner("camera_server", common);
    auto node = sb::camera_server::CameraServerNode::create(*params, runner);
    if (!node) {
      std::fprintf(stderr, "camera_server: %s\n", node.error().c_str());
      return 2;
    }
    return runner.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "camera_server: %s\n", e.what());
    return 1;
  }
}
