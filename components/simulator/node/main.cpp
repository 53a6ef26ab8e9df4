// simulator: the built-in stand-in for the cameras and the robot base. Renders a scenario,
// publishes stereo/frame, sim/ground_truth and stereo/calibration, obeys cmd/velocity.

#include "common/util/cli11.hpp"

#include <memory>
#include <optional>
#include <string>

#include "common/node/run_node.hpp"
#include "simulator/io/scenario_file.hpp"
#include "simulator/io/sim_params_file.hpp"
#include "simulator/node/simulator_node.hpp"
#include "stereo/frame/frame_codec_flags.hpp"
#include "stereo/io/calibration_file.hpp"

namespace sb = stereoball;

namespace {

// The simulator's flags (besides the common ones).
struct Flags {
  std::string scenario_name = "ball_rolling_away";
  std::string scenarios_dir;  // searched in add(), once the roles' settings are read
  std::string calibration_path;
  sb::simulator::SimulatorNodeOptions options;
  std::optional<sb::stereo::FrameCodecFlags> codec;

  void add(CLI::App& app) {
    scenarios_dir = sb::node::default_config_path("scenarios");
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
    app.add_option("--base-log", options.base_log_path,
                   "append the base's events (every executed command with its authentication "
                   "and age, e-stop changes, the robot's velocity per frame) to this file");
    codec.emplace(app);
  }
};

// Everything the node is built from, checked before any DDS entity exists.
struct Setup {
  sb::simulator::SimParams params;
  sb::simulator::Scenario scenario;
  sb::stereo::StereoCalibration published;
  sb::simulator::SimulatorNodeOptions options;
};

sb::Result<Setup> configure(const sb::node::CommonOptions& common, const Flags& flags) {
  auto config = sb::simulator::load_simulator_config(common.config_path);
  if (!config) return sb::Error{config.error()};
  sb::simulator::SimulatorNodeOptions options = flags.options;
  options.output = config->output;
  flags.codec->apply(options.output);
  auto scenario = sb::simulator::load_scenario_by_name(flags.scenario_name, flags.scenarios_dir);
  if (!scenario) return sb::Error{scenario.error()};
  const sb::simulator::SimParams& params = config->sim;
  if (auto e = sb::simulator::Simulator::check(params, *scenario); !e) return sb::Error{e.error()};
  const sb::simulator::StereoRig rig(params);
  sb::stereo::StereoCalibration published = rig.calibration();
  if (!flags.calibration_path.empty()) {
    const std::string& path = flags.calibration_path;
    auto loaded = sb::stereo::load_calibration(path);
    if (!loaded) return sb::Error{"--calibration: " + loaded.error()};
    if (loaded->image_size != published.image_size) {
      return sb::Error{
          "--calibration " + path + ": image size " + std::to_string(loaded->image_size.width) +
          "x" + std::to_string(loaded->image_size.height) + " does not match the simulator's " +
          std::to_string(published.image_size.width) + "x" +
          std::to_string(published.image_size.height)};
    }
    published = loaded.value();
    options.calibration_source = path;
  }
  return Setup{params, std::move(scenario).value(), published, options};
}

}  // namespace

int main(int argc, char** argv) {
  const char* help =
      "simulator: a simulated stereo rig on a differential-drive robot in a room. Publishes\n"
      "stereo/frame (raw bgr8, or jpeg/png per eye with frame_encoding) at frame_rate_hz x\n"
      "--rate, sim/ground_truth per frame\n"
      "and stereo/calibration (latched: the rig's true calibration, or --calibration FILE);\n"
      "drives the base from cmd/velocity (stale commands stop it).";
  Flags flags;
  const sb::node::NodeMain node{"simulator", help, "simulator.yaml",
                                sb::params::specs(sb::simulator::simulator_config_fields()),
                                [&flags](CLI::App& app) { flags.add(app); }};
  return sb::node::run_node(
      argc, argv, node,
      [&flags](const sb::node::CommonOptions& common) { return configure(common, flags); },
      [](sb::node::Runner& runner, const Setup& setup) {
        return sb::node::NodeHandle(std::make_shared<sb::simulator::SimulatorNode>(
            runner, setup.params, setup.scenario, setup.published, setup.options));
      });
}
