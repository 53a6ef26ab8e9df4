// stereoball doctor: joins a running deployment (domain, partition, key), listens for a few
// seconds and prints one line per check: verdict (ok / warn / FAIL / n/a), what it saw and,
// when something is wrong, the fix. Exit status 1 when any check fails; --json for machines.

#include "common/util/cli11.hpp"

#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "camera_server/node/camera_server_params_file.hpp"
#include "collect.hpp"
#include "common/node/common_flags.hpp"
#include "common/util/install_layout.hpp"
#include "doctor_checks.hpp"
#include "installed_profile.hpp"

namespace sb = stereoball;

namespace {

int fail(const std::string& message) {
  std::fprintf(stderr, "stereoball doctor: %s\n", message.c_str());
  return 2;
}

// The --config a profile passes to camera_server, if any.
std::string camera_config_of(const sb::launch::Profile& profile) {
  for (const auto& node : profile.nodes) {
    if (std::filesystem::path(node.program).filename() != "camera_server") continue;
    for (size_t i = 0; i + 1 < node.args.size(); ++i)
      if (node.args[i] == "--config" || node.args[i] == "-c") return node.args[i + 1];
  }
  return {};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "stereoball doctor: checks a running deployment (nodes, cameras, eye order and skew,\n"
      "calibration, row error, exposure, keys, clocks, e-stop) and says how to fix what fails.\n"
      "Exit status: 0 nothing failed, 1 a check failed, 2 bad arguments or DDS unusable."};
  sb::doctor::CollectOptions options;
  sb::node::add_common_flags(app, options.common, "", false);
  app.add_option("--listen-s", options.listen_s, "seconds to listen")
      ->check(CLI::Range(1.0, 120.0))
      ->capture_default_str();
  app.add_option("--pairs", options.pairs, "live stereo pairs measured (eye order, row error)")
      ->check(CLI::Range(0, 20))
      ->capture_default_str();
  std::vector<std::string> profiles, expected;
  app.add_option("--profile", profiles,
                 "launch profile(s) that run here (deploy/NAME.yaml): their nodes must answer, "
                 "their camera_server config gives the configured mode");
  app.add_option("--expect", expected, "components that must answer (e.g. camera_server)")
      ->delimiter(',');
  std::string camera_config;
  app.add_option("--camera-config", camera_config,
                 "camera_server config the deployment runs with (default: the profile's, else "
                 "camera_server.yaml by the config search order)");
  bool json = false;
  app.add_flag("--json", json, "one JSON object instead of lines");
  CLI11_PARSE(app, argc, argv);

  std::set<std::string> expected_set(expected.begin(), expected.end());
  for (const auto& name : profiles) {
    auto profile = sb::launch::load_profile_for_this_program(name);
    if (!profile) return fail(profile.error());
    for (const auto& node : profile->nodes)
      if (!node.optional)
        expected_set.insert(std::filesystem::path(node.program).filename().string());
    if (camera_config.empty()) camera_config = camera_config_of(*profile);
  }
  std::string config_note;
  if (camera_config.empty()) {
    auto found = sb::paths::find_config("camera_server.yaml", sb::paths::default_roots());
    if (found)
      camera_config = found->path.string();
    else
      config_note = "no camera_server.yaml found: " + found.error();
  }

  sb::doctor::Observations obs;
  try {
    obs = sb::doctor::collect(options);
  } catch (const std::exception& e) {
    return fail(e.what());
  }
  obs.expected_nodes.assign(expected_set.begin(), expected_set.end());
  if (!camera_config.empty()) {
    auto params = sb::camera_server::load_camera_server_params(camera_config);
    if (params) {
      obs.camera_config = sb::doctor::CameraConfig{camera_config, params->source, params->width_px,
                                                   params->height_px, params->rate_hz};
    } else {
      config_note = params.error();
    }
  }
  obs.camera_config_note = config_note;

  const auto checks = sb::doctor::run_checks(obs);
  const std::string out = json ? sb::doctor::to_json(checks) : sb::doctor::to_text(checks);
  std::fwrite(out.data(), 1, out.size(), stdout);
  return sb::doctor::exit_status(checks);
}
