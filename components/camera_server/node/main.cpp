// camera_server: two V4L2 cameras (or image files) -> stereo/frame + stereo/calibration.

#include <optional>

#include "camera_server/node/camera_server_node.hpp"
#include "camera_server/node/camera_server_params_file.hpp"
#include "common/node/run_node.hpp"
#include "stereo/frame/frame_codec_flags.hpp"

namespace sb = stereoball;

int main(int argc, char** argv) {
  const char* help =
      "camera_server: captures two V4L2 cameras (or plays left/right image files), pairs the "
      "frames by capture stamp and publishes stereo/frame; publishes the calibration file on "
      "stereo/calibration (transient-local). Parameters: components/camera_server/README.md.";
  std::optional<sb::stereo::FrameCodecFlags> codec_flags;
  const sb::node::NodeMain node{"camera_server", help, "camera_server.yaml",
                                sb::params::specs(sb::camera_server::camera_server_fields()),
                                [&codec_flags](CLI::App& app) { codec_flags.emplace(app); }};
  return sb::node::run_node(
      argc, argv, node,
      [&codec_flags](const sb::node::CommonOptions& common) {
        auto params = sb::camera_server::load_camera_server_params(common.config_path);
        if (params) codec_flags->apply(params->output);
        return params;
      },
      [](sb::node::Runner& runner,
         const sb::camera_server::CameraServerParams& params) -> sb::Result<sb::node::NodeHandle> {
        auto server = sb::camera_server::CameraServerNode::create(params, runner);
        if (!server) return sb::Error{server.error()};
        return sb::node::NodeHandle(std::move(server).value());
      });
}
