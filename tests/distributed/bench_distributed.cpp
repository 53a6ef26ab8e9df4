// stereoball-bench-distributed: figures for robot and workstation as two hosts (two network
// namespaces joined by veth, LAN Cyclone configuration). Needs root. Prints only.
//  1. Frame transport robot -> workstation: sb_frame_publisher (raw bgr8 and JPEG) in the
//     robot namespace, an observer in the workstation namespace: rate, loss, latency.
//  2. The whole system (robot + workstation profiles): frame latency across the link, and the
//     end-to-end time from frame capture to the velocity command it produced (defined below).

#include <signal.h>
#include <unistd.h>
#include "common/util/cli11.hpp"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "common/dds/participant.hpp"
#include "frame_transport.hpp"
#include "two_host_system.hpp"

namespace sb = stereoball;
namespace sd = stereoball::distributed;
using namespace std::chrono_literals;

namespace {

std::string lan_uri() {
  return "file://" + sb::testing::source_path("config/cyclonedds/lan.xml");
}

// A copy of lan.xml whose socket receive buffer is capped at rcvbuf (e.g. "208KB": what a
// default Debian kernel, rmem_max = 212992, grants), to show what the kernel setting buys.
std::string capped_lan_uri(const std::string& rcvbuf) {
  std::ifstream in(sb::testing::source_path("config/cyclonedds/lan.xml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string xml = text.str();
  const std::string from = "<SocketReceiveBufferSize min=\"default\" max=\"32MB\"/>";
  const auto pos = xml.find(from);
  if (pos == std::string::npos) return "";
  xml.replace(pos, from.size(),
              "<SocketReceiveBufferSize min=\"default\" max=\"" + rcvbuf + "\"/>");
  const std::string path = sb::testing::temp_dir() + "/lan-capped.xml";
  std::ofstream(path) << xml;
  return "file://" + path;
}

double ms(int64_t ns) {
  return static_cast<double>(ns) / 1e6;
}

void print_latency(const char* what, const std::vector<double>& values_ms) {
  std::printf("  %-44s n=%-5zu p50 %7.2f ms  p99 %7.2f ms  max %7.2f ms\n", what, values_ms.size(),
              sd::percentile(values_ms, 50), sd::percentile(values_ms, 99),
              sd::percentile(values_ms, 100));
}

// Rate of samples between the first and last receive time, Hz.
template <typename T>
double rate_hz(const std::vector<T>& rx) {
  if (rx.size() < 2) return 0.0;
  return static_cast<double>(rx.size() - 1) / (ms(rx.back().rx_ns - rx.front().rx_ns) / 1e3);
}

int transport(const std::string& encoding, int quality, double duration_s, int domain,
              const std::string& receiver_uri, const std::string& label) {
  sd::TwoHosts hosts;
  if (auto e = hosts.setup(); !e) {
    std::fprintf(stderr, "stereoball-bench-distributed: %s\n", e.error().c_str());
    return 1;
  }
  sd::FrameTransportOptions options;
  options.encoding = encoding;
  options.quality = quality;
  options.duration_s = duration_s;
  options.domain = domain;
  options.receiver_uri = receiver_uri;
  const auto run = sd::run_frame_transport(hosts, options);
  if (!run) {
    std::fprintf(stderr, "stereoball-bench-distributed: %s\n", run.error().c_str());
    return 1;
  }
  const long sent = run->sent;
  const auto& frames = run->received;
  std::vector<double> latency;
  double bytes = 0;
  for (const auto& f : frames) {
    latency.push_back(ms(f.rx_ns - f.stamp_ns));
    bytes += static_cast<double>(f.bytes);
  }
  const double mean_bytes = frames.empty() ? 0 : bytes / static_cast<double>(frames.size());
  std::printf("%s%s%s: sent %ld, received %zu (%.1f%% lost), %.1f Hz, %.0f KiB/pair, %.1f Mbit/s\n",
              encoding.c_str(), encoding == "jpeg" ? (" q" + std::to_string(quality)).c_str() : "",
              label.c_str(), sent, frames.size(),
              100.0 * (1.0 - static_cast<double>(frames.size()) / static_cast<double>(sent)),
              rate_hz(frames), mean_bytes / 1024, mean_bytes * 8 * rate_hz(frames) / 1e6);
  print_latency("publish -> received in other namespace", latency);
  if (frames.empty()) {
    std::fprintf(stderr, "stereoball-bench-distributed: no %s frame crossed the link\n",
                 encoding.c_str());
    return 1;
  }
  return 0;
}

int system_run(double duration_s, int domain, const std::string& robot_profile) {
  sd::SystemOptions o;
  o.domain = domain;
  o.robot_profile = robot_profile;
  o.partition = "sbbench.system." + std::to_string(::getpid());
  o.workstation_observer_topics = {"frame", "detection"};
  sd::TwoHostSystem system(o);
  if (auto e = system.start(); !e) {
    std::fprintf(stderr, "stereoball-bench-distributed: %s\n", e.error().c_str());
    return 1;
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<int>(duration_s * 1e3)));
  const auto robot = system.robot_log();
  const auto ws = system.workstation_log();
  std::vector<double> frame_latency, detect, track_at_robot, e2e, controller_wait;
  for (const auto& f : ws.frames) frame_latency.push_back(ms(f.rx_ns - f.stamp_ns));
  for (const auto& d : ws.detections) detect.push_back(ms(d.publish_ns - d.capture_ns));
  for (const auto& t : robot.tracks) track_at_robot.push_back(ms(t.rx_ns - t.capture_ns));
  // End to end, per frame: from StereoFrame.stamp_ns (the simulator's capture/publish time,
  // carried as BallDetection/BallTrack.capture_stamp_ns) to VelocityCommand.stamp_ns of the
  // first command issued after that frame's track reached the robot namespace, counted only
  // when that track was still the newest one at that command (so it determined the command).
  size_t c = 0;
  for (size_t i = 0; i < robot.tracks.size(); ++i) {
    const auto& t = robot.tracks[i];
    while (c < robot.commands.size() && robot.commands[c].stamp_ns < t.rx_ns) ++c;
    if (c == robot.commands.size()) break;
    const bool superseded =
        i + 1 < robot.tracks.size() && robot.tracks[i + 1].rx_ns <= robot.commands[c].stamp_ns;
    if (superseded) continue;
    e2e.push_back(ms(robot.commands[c].stamp_ns - t.capture_ns));
    controller_wait.push_back(ms(robot.commands[c].stamp_ns - t.rx_ns));
  }
  size_t following = 0;
  for (const auto& t : robot.tracks) following += t.state == sd::kTrackFollowing;
  std::printf(
      "system (%s + workstation profiles, %.0f s): frames at workstation %.1f Hz, "
      "detections %.1f Hz, tracks at robot %.1f Hz (%zu FOLLOWING), commands %.1f Hz\n",
      robot_profile.c_str(), duration_s, rate_hz(ws.frames), rate_hz(ws.detections),
      rate_hz(robot.tracks), following, rate_hz(robot.commands));
  print_latency("frame: simulator publish -> workstation", frame_latency);
  print_latency("detection: capture -> detector publish", detect);
  print_latency("track: capture -> received in robot ns", track_at_robot);
  print_latency("controller wait: track rx -> next command", controller_wait);
  print_latency("end to end: capture -> velocity command", e2e);
  if (e2e.empty()) std::printf("%s\n", system.diagnostics().c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "stereoball-bench-distributed: frame transport and capture-to-command time between two\n"
      "network namespaces joined by veth (needs root and iproute2; prints figures only)"};
  double transport_s = 10, system_s = 30;
  int quality = 90;
  int domain = sb::dds::domain_from_env(0);
  bool skip_transport = false, skip_system = false;
  app.add_option("--transport-duration", transport_s, "seconds per transport run")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--system-duration", system_s, "seconds of the whole-system run")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--quality", quality, "JPEG quality of the compressed run")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  app.add_option("--domain", domain, "DDS domain")
      ->check(CLI::Range(0, 232))
      ->capture_default_str();
  app.add_flag("--no-transport", skip_transport, "skip the frame transport runs");
  app.add_flag("--no-system", skip_system, "skip the whole-system run");
  std::string robot_profile = "robot";
  app.add_option("--robot-profile", robot_profile,
                 "robot profile of the whole-system run (robot-jpeg: JPEG frames over the link)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  int rc = 0;
  if (!skip_transport) {
    rc |= transport("bgr8", quality, transport_s, domain, lan_uri(), "");
    rc |= transport("jpeg", quality, transport_s, domain, lan_uri(), "");
    const std::string capped = capped_lan_uri("212992B");
    if (capped.empty()) {
      std::fprintf(stderr,
                   "stereoball-bench-distributed: lan.xml has no 32MB receive buffer line\n");
    } else {
      const std::string note =
          " (receiver socket buffer capped at 212992 B = Debian default rmem_max)";
      rc |= transport("bgr8", quality, transport_s, domain, capped, note);
      rc |= transport("jpeg", quality, transport_s, domain, capped, note);
    }
  }
  if (!skip_system) rc |= system_run(system_s, domain, robot_profile);
  return rc;
}
