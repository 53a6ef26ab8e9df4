#include "frame_transport.hpp"

#include <unistd.h>

#include <chrono>
#include <thread>

#include "process.hpp"
#include "two_host_system.hpp"

namespace stereoball::distributed {

Result<FrameTransport> run_frame_transport(TwoHosts& hosts, const FrameTransportOptions& options) {
  using namespace std::chrono_literals;
  const std::string lan = "file://" + testing::source_path("config/cyclonedds/lan.xml");
  // Both ends need the deployment key to leave loopback.
  const std::string key_file = testing::temp_dir() + "/deployment.key";
  auto [key_code, key_output] =
      testing::run({testing::bin("stereoball-keys"), "init", "--file", key_file}, 20s);
  if (key_code != 0) return Error{"stereoball-keys init failed: " + key_output};
  hosts.set_key_file(key_file);

  const std::string partition =
      options.partition.empty() ? "sbbench." + std::to_string(::getpid()) : options.partition;
  const std::vector<std::string> common{"--domain", std::to_string(options.domain), "--partition",
                                        partition};
  std::vector<std::string> obs{testing::bin("sb_netns_observer"), "--topics", "frame"};
  obs.insert(obs.end(), common.begin(), common.end());
  GentleProcess observer(testing::Process::start(hosts.command(
      hosts.workstation(), obs, options.receiver_uri.empty() ? lan : options.receiver_uri)));
  if (!observer.get().wait_for_output("# observing", 10s)) {
    return Error{"observer did not start: " + observer.get().output()};
  }
  std::this_thread::sleep_for(2s);  // discovery across the link
  std::vector<std::string> pub{testing::bin("sb_frame_publisher"),
                               "--encoding",
                               options.encoding,
                               "--quality",
                               std::to_string(options.quality),
                               "--rate",
                               std::to_string(options.rate_hz),
                               "--duration",
                               std::to_string(options.duration_s)};
  pub.insert(pub.end(), common.begin(), common.end());
  testing::Process publisher = testing::Process::start(hosts.command(hosts.robot(), pub, lan));
  const auto code = publisher.wait_for_exit(
      std::chrono::milliseconds(static_cast<int>(options.duration_s * 1e3) + 30'000));
  std::this_thread::sleep_for(500ms);  // the last frames in flight
  const std::string out = publisher.output();
  const auto pos = out.find("# sent ");
  FrameTransport run;
  run.sent = pos == std::string::npos ? -1 : std::stol(out.substr(pos + 7));
  if (!code || *code != 0 || run.sent <= 0) return Error{"publisher failed: " + out};
  run.received = parse_observer_log(observer.get().output()).frames;
  return run;
}

}  // namespace stereoball::distributed
