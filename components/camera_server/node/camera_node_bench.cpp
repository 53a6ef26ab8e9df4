// stereoball-bench-camera-node: starts the real camera_server with the file source (13 real
// pairs, 640x480) and measures, in a subscriber, capture-to-receive latency (tick stamp ->
// sample delivered, DDS included) and the node's CPU per frame published in the measured window
// (camera_node_window.hpp). Prints figures only.

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>
#include "common/util/cli11.hpp"

#include "camera_server/node/camera_node_window.hpp"
#include "common/dds/reader.hpp"
#include "common/node/node_runner.hpp"

extern char** environ;
namespace sb = stereoball;

namespace {

// utime + stime of pid, seconds.
double cpu_seconds(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t close = text.rfind(')');
  if (close == std::string::npos) return 0;
  std::istringstream rest(text.substr(close + 2));
  std::string field;
  double ticks = 0;
  for (int i = 3; i <= 15 && rest >> field; ++i) {
    if (i == 14 || i == 15) ticks += std::stod(field);
  }
  return ticks / static_cast<double>(sysconf(_SC_CLK_TCK));
}

}  // namespace

int main(int argc, char** argv) {
  sb::node::block_termination_signals();
  CLI::App app{
      "camera_server end-to-end timing with the file source: capture (tick) -> "
      "subscriber receive latency and node CPU per frame. Prints figures only."};
  sb::node::CommonOptions common;
  sb::node::add_common_flags(app, common, "", false);
  double seconds = 10.0;
  double rate_hz = 30.0;
  std::string encoding = "as_read";
  app.add_option("--seconds", seconds, "measurement length, s")->capture_default_str();
  app.add_option("--rate", rate_hz, "playback rate, Hz")->capture_default_str();
  app.add_option("--file-encoding", encoding, "as_read (mono8) | bgr8 | mono8")
      ->capture_default_str();
  std::string frame_encoding = "raw";
  app.add_option("--frame-encoding", frame_encoding, "raw | jpeg | png: how the node publishes")
      ->check(CLI::IsMember({"raw", "jpeg", "png"}))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  if (common.partition.empty()) common.partition = "bench_camera_" + std::to_string(getpid());

  const std::string config = "/tmp/sb_bench_camera_" + std::to_string(getpid()) + ".yaml";
  std::ofstream(config) << "source: files\nleft_glob: " SB_SHARED_DATA_DIR
                           "/opencv-samples/left*.jpg\nright_glob: " SB_SHARED_DATA_DIR
                           "/opencv-samples/right*.jpg\nfile_encoding: "
                        << encoding << "\nframe_encoding: " << frame_encoding
                        << "\nwidth_px: 640\nheight_px: 480\nrate_hz: " << rate_hz
                        << "\ncalibration_file: " SB_SOURCE_DIR
                           "/config/calibration/opencv_samples_stereo.yaml\n";
  const std::string bin = SB_BIN_DIR "/camera_server";
  const std::string domain = std::to_string(common.domain_id);
  std::vector<std::string> args{bin,           "--config",       config,        "--domain", domain,
                                "--partition", common.partition, "--log-level", "warn"};
  std::vector<char*> cargs;
  for (auto& a : args) cargs.push_back(a.data());
  cargs.push_back(nullptr);
  pid_t pid = -1;
  if (posix_spawn(&pid, bin.c_str(), nullptr, nullptr, cargs.data(), environ) != 0) {
    std::fprintf(stderr, "cannot start %s\n", bin.c_str());
    return 1;
  }

  std::vector<double> latency_us;
  size_t bytes = 0;
  sb::camera_server::WindowMark start, end;
  int rc = 0;
  {
    sb::node::Runner runner("bench_camera_node", common);
    runner.set_heartbeat_period(0);
    sb::dds::DataReader<stereoball_msg_StereoFrame> frames(runner.participant(),
                                                           sb::topics::kStereoFrame);
    if (!frames.wait_for_writers(1, 10'000'000'000)) {
      std::fprintf(stderr, "camera_server did not start (see its output above)\n");
      kill(pid, SIGKILL);
      waitpid(pid, nullptr, 0);
      return 1;
    }
    enum class Phase { kWarmUp, kMeasuring, kDone } phase = Phase::kWarmUp;
    bool received = false;
    uint64_t last_seq = 0;
    runner.on_data(frames.handle(), [&] {
      const int64_t now = sb::node::now_ns();
      for (auto& s : frames.take()) {
        if (phase == Phase::kMeasuring) latency_us.push_back((now - s->stamp_ns) * 1e-3);
        bytes = s->left.data._length + s->right.data._length;
        last_seq = std::max(last_seq, s->seq);
        received = true;
      }
    });
    // At least one second of warm-up (discovery, first allocations) and a first frame, then
    // measure; both ends of the window read the node's CPU and the newest seq together.
    runner.every(1'000'000'000, [&](int64_t now) {
      if (phase == Phase::kWarmUp && received) {
        phase = Phase::kMeasuring;
        start = {now, cpu_seconds(pid), last_seq};
      } else if (phase == Phase::kMeasuring &&
                 now - start.now_ns >= static_cast<int64_t>(seconds * 1e9)) {
        phase = Phase::kDone;
        end = {now, cpu_seconds(pid), last_seq};
        runner.stop();
      }
    });
    rc = runner.run();
  }
  kill(pid, SIGINT);
  waitpid(pid, nullptr, 0);
  std::remove(config.c_str());
  if (latency_us.empty()) {
    std::fprintf(stderr, "no frames received\n");
    return 1;
  }
  const auto window = sb::camera_server::window_figures(start, end);
  if (!window) {
    std::fprintf(stderr, "%s\n", window.error().c_str());
    return 1;
  }
  std::sort(latency_us.begin(), latency_us.end());
  const size_t n = latency_us.size();
  std::printf("camera_server file source (%s), 640x480 asked for %.0f Hz, %zu bytes per frame:\n",
              encoding.c_str(), rate_hz, bytes);
  std::printf("  frames published     %llu in %.1f s (%.1f Hz; seq advance), %zu received\n",
              static_cast<unsigned long long>(window->published), window->wall_s,
              window->published_hz, n);
  std::printf("  tick -> received     median %.1f us  p90 %.1f us  p99 %.1f us  max %.1f us\n",
              latency_us[n / 2], latency_us[n * 9 / 10], latency_us[std::min(n - 1, n * 99 / 100)],
              latency_us.back());
  std::printf("  node CPU             %.2f %% of one core = %.0f us per published frame\n",
              window->cpu_percent, window->cpu_us_per_frame);
  return rc;
}
