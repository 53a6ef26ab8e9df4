// simulator: the built-in stand-in for the cameras and the robot base. Renders a scenario,
// publishes stereo/frame, sim/ground_truth and stereo/calibration, obeys cmd/velocity.

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <string>

#include "common/node/common_flags.hpp"
#include "common/node/node_runner.hpp"
#include "simulator/io/scenario_file.hpp"
#include "simulator/io/sim_params_file.hpp"
#include "simulator/node/simulator_node.hpp"
#include "stereo/frame/frame_codec_flags.hpp"
#include "stereo/io/calibration_file.hpp"

namespace {

int fail(const std::string& message) {
  std::fprintf(stderr, "simulator: %s\n", message.c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  namespace sb = stereoball;
  sb::node::block_termination_signals();
  CLI::App app{
      "simulator: a simulated stereo rig on a differential-drive robot in a room. Publishes\n"
      "stereo/frame (raw bgr8, or jpeg/png per eye with frame_encoding) at frame_rate_hz x\n"
      "--rate, sim/ground_truth per frame\n"
      "and stereo/calibration (latched: the rig's true calibration, or --calibration FILE);\n"
      "drives the base from cmd/velocity (stale commands stop it)."};
  sb::node::CommonOptions common;
  sb::node::add_common_flags(app, common, "simulator.yaml");
  sb::node::add_help_params(app, sb::params::specs(sb::simulator::simulator_config_fields()));
  std::string scenario_name = "ball_rolling_away";
  std::string scenarios_dir = sb::node::default_config_path("scenarios");
  std::string calibration_path;
  sb::simulator::SimulatorNodeOptions options;
  app.add_option("--scenario", scenario_name,
                 "scenario name (in --scenarios-dir) or path to a scenario file")
      ->capture_default_str();
  app.add_option("--scenarios-dir", scenarios_dir, "folder of scenario files")
      ->capture_default_str();
  app.add_option("--rate", options.rate,
                 "simulated seconds per wall second (1 = real time, 0.5 = half speed)")
      ->check(CLI::Range(0.01, 100.0))
      ->capture_default_str();
  app.add_option("--calibration", calibration_path,
                 "publish this calibration file instead of the true one (calibrated-vs-true "
                 "mismatch tests); its image size must match the simulator's");
  app.add_flag("--loop", options.loop, "restart the scenario when its duration has passed");
  const sb::stereo::FrameCodecFlags codec_flags(app);
  CLI11_PARSE(app, argc, argv);

  auto config = sb::simulator::load_simulator_config(common.config_path);
  if (!config) return fail(config.error());
  const sb::simulator::SimParams& params = config->sim;
  options.output = config->output;
  codec_flags.apply(options.output);
  auto scenario = sb::simulator::load_scenario_by_name(scenario_name, scenarios_dir);
  if (!scenario) return fail(scenario.error());
  if (auto e = sb::simulator::Simulator::check(params, *scenario); !e) return fail(e.error());
  const sb::simulator::StereoRig rig(params);
  sb::stereo::StereoCalibration published = rig.calibration();
  if (!calibration_path.empty()) {
    auto loaded = sb::stereo::load_calibration(calibration_path);
    if (!loaded) return fail("--calibration: " + loaded.error());
    if (loaded->image_size != published.image_size) {
      return fail("--calibration " + calibration_path + ": image size " +
                  std::to_string(loaded->image_size.width) + "x" +
                  std::to_string(loaded->image_size.height) + " does not match the simulator's " +
                  std::to_string(published.image_size.width) + "x" +
                  std::to_string(published.image_size.height));
    }
    published = loaded.value();
    options.calibration_source = calibration_path;
  }
  try {
    sb::node::Runner runner("simulator", common);
    sb::simulator::SimulatorNode node(runner, params, *scenario, published, options);
    return runner.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "simulator: %s\n", e.what());
    return 1;
  }
}
