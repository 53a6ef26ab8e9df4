// stereoball launch PROFILE: start the nodes of deploy/PROFILE.yaml and supervise them
// (restart crashed nodes with back-off; Ctrl-C or SIGTERM stops them all, then exits 0).

#include <signal.h>
#include <unistd.h>
#include "common/util/cli11.hpp"

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "common/node/node_runner.hpp"
#include "common/util/deployment.hpp"
#include "common/util/log.hpp"
#include "installed_profile.hpp"
#include "supervisor.hpp"

namespace sb = stereoball;
namespace fs = std::filesystem;

namespace {
std::atomic<bool> g_stop{false};
void on_signal(int) {
  g_stop = true;
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"stereoball launch: start and supervise a deploy/ profile"};
  std::string profile_name, log_path = "stereoball-launch.log", partition;
  // Run by hand on a host with a systemd role, the launcher sees its settings as the unit would.
  sb::deployment::import_env_file();
  int domain = sb::dds::domain_from_env(0);
  double duration_s = 0;
  app.add_option("profile", profile_name, "profile name (deploy/NAME.yaml) or path")->required();
  app.add_option("--domain", domain, "DDS domain for every node")
      ->check(CLI::Range(0, 232))
      ->capture_default_str();
  app.add_option("--partition", partition, "DDS partition for every node");
  app.add_option("--log", log_path, "file that collects every node's output")
      ->capture_default_str();
  app.add_option("--duration", duration_s, "stop after S seconds (0 = until Ctrl-C)")
      ->check(CLI::NonNegativeNumber);
  CLI11_PARSE(app, argc, argv);
  sb::log::init("launch");

  auto profile = sb::launch::load_profile_for_this_program(profile_name);
  if (!profile) {
    std::fprintf(stderr, "stereoball launch: %s\n", profile.error().c_str());
    return 2;
  }
  sb::launch::SupervisorOptions options;
  options.bin_dir = fs::read_symlink("/proc/self/exe").parent_path().string();
  options.log_path = log_path;
  options.extra_args = {"--domain", std::to_string(domain)};
  if (!partition.empty())
    options.extra_args.insert(options.extra_args.end(), {"--partition", partition});
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  sb::launch::Supervisor supervisor(*profile, options,
                                    [](const std::string& e) { sb::log::info(e); });
  sb::log::info("profile ", profile->name, ": ", profile->description, " (logs: ", log_path, ")");
  sb::log::info("DDS configuration of the nodes: ",
                profile->cyclonedds_config.empty()
                    ? std::string("each node's own (the profile names none)")
                    : sb::deployment::file_uri(profile->cyclonedds_config));
  if (auto started = supervisor.start_all(sb::node::monotonic_ns()); !started) {
    std::fprintf(stderr, "stereoball launch: %s\n", started.error().c_str());
    supervisor.stop_all();
    return 2;
  }
  const int64_t end = duration_s > 0
                          ? sb::node::monotonic_ns() + static_cast<int64_t>(duration_s * 1e9)
                          : INT64_MAX;
  while (!g_stop && sb::node::monotonic_ns() < end) {
    supervisor.poll(sb::node::monotonic_ns());
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  sb::log::info("stopping all nodes");
  const bool clean = supervisor.stop_all();
  sb::log::info(clean ? "all nodes stopped cleanly"
                      : "some nodes did not stop cleanly (see the log)");
  return 0;
}
