// stereoball bench viewer: what `stereoball view` costs. Publishes a synthetic 640x480 stereo
// pair (moving texture) with detections and tracks at 30 Hz, starts stereoball-view, and
// prints (1) the viewer's CPU and the frame topic's reader count with no client, (2) CPU,
// image rate and capture-to-client latency with 1, 2 and 4 page-like clients (they read every
// message and acknowledge each pair, as the page does), (3) the viewer's resident memory while
// 10 clients connect and disconnect in a loop.

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <sstream>
#include <thread>
#include <vector>

#include "common/dds/participant.hpp"
#include "common/dds/writer.hpp"
#include "stereoball/topics.hpp"
#include "ws_client.hpp"

extern char** environ;
namespace sb = stereoball;
using namespace std::chrono_literals;

namespace {

struct Options {
  int width = 640, height = 480;
  double rate_hz = 30;
  double phase_s = 10;
  double loop_s = 60;
  int domain = sb::dds::domain_from_env(0);
};

int64_t wall_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// CPU seconds (user + system) of a process so far.
double cpu_s(pid_t pid) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  std::getline(f, line);
  std::istringstream rest(line.substr(line.rfind(')') + 2));
  std::string field;
  std::vector<std::string> fields;
  while (rest >> field) fields.push_back(field);
  if (fields.size() < 13) return 0;
  return (std::stod(fields[11]) + std::stod(fields[12])) / sysconf(_SC_CLK_TCK);
}

// Resident memory of a process, MB.
double rss_mb(pid_t pid) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return 0;
}

// The camera and the rest of the pipeline, as far as the viewer can tell.
class Publisher {
 public:
  Publisher(const Options& o, const std::string& partition) {
    thread_ = std::thread([this, o, partition] {
      sb::dds::DomainParticipant p({o.domain, partition});
      frames_ = std::make_unique<sb::dds::DataWriter<stereoball_msg_StereoFrame>>(
          p, sb::topics::kStereoFrame);
      sb::dds::DataWriter<stereoball_msg_BallDetection> detections(p, sb::topics::kBallDetection);
      sb::dds::DataWriter<stereoball_msg_BallTrack> tracks(p, sb::topics::kBallTrack);
      // A texture wider than the image, shifted a little every frame: JPEG sizes are those of
      // a moving scene, at the cost of one copy per frame.
      const int margin = 256;
      const int wide = o.width + margin;
      std::vector<uint8_t> texture(static_cast<size_t>(wide) * o.height * 3);
      for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < wide; ++x) {
          uint8_t* px = &texture[(static_cast<size_t>(y) * wide + x) * 3];
          const double v = std::sin(x * 0.05) * std::cos(y * 0.07);
          px[0] = static_cast<uint8_t>(128 + 100 * v);
          px[1] = static_cast<uint8_t>((x ^ y) & 0xff);
          px[2] = static_cast<uint8_t>(128 - 100 * v);
        }
      std::vector<uint8_t> image(static_cast<size_t>(o.width) * o.height * 3);
      char source[] = "bench", encoding[] = "bgr8", reason[] = "bench";
      const auto period = std::chrono::nanoseconds(static_cast<int64_t>(1e9 / o.rate_hz));
      auto next = std::chrono::steady_clock::now();
      for (uint64_t seq = 0; !stop_; ++seq) {
        const size_t shift = (seq * 3) % margin;
        for (int y = 0; y < o.height; ++y)
          std::memcpy(&image[static_cast<size_t>(y) * o.width * 3],
                      &texture[(static_cast<size_t>(y) * wide + shift) * 3],
                      static_cast<size_t>(o.width) * 3);
        stereoball_msg_StereoFrame f{};
        f.seq = seq;
        f.stamp_ns = wall_ns();
        f.source = source;
        f.encoding = encoding;
        for (auto* eye : {&f.left, &f.right}) {
          eye->capture_stamp_ns = f.stamp_ns;
          eye->width_px = static_cast<uint32_t>(o.width);
          eye->height_px = static_cast<uint32_t>(o.height);
          eye->step_bytes = static_cast<uint32_t>(o.width * 3);
          eye->data._buffer = image.data();
          eye->data._length = static_cast<uint32_t>(image.size());
        }
        frames_->write(f);
        stereoball_msg_BallDetection d{};
        d.frame_seq = seq;
        d.capture_stamp_ns = f.stamp_ns;
        d.reason = reason;
        d.left = {320, 240, 20, 0.9f};
        detections.write(d);
        stereoball_msg_BallTrack t{};
        t.frame_seq = seq;
        t.capture_stamp_ns = f.stamp_ns;
        t.reason = reason;
        tracks.write(t);
        next += period;
        std::this_thread::sleep_until(next);
      }
      frames_.reset();
    });
  }
  ~Publisher() {
    stop_ = true;
    thread_.join();
  }
  /// Readers of stereo/frame matched with the camera's writer right now.
  uint32_t frame_readers() const { return frames_ ? frames_->matched_readers() : 0; }

 private:
  std::atomic<bool> stop_{false};
  std::unique_ptr<sb::dds::DataWriter<stereoball_msg_StereoFrame>> frames_;
  std::thread thread_;
};

pid_t start_viewer(const Options& o, const std::string& partition, const std::string& log,
                   int& port) {
  const std::string bin =
      std::filesystem::read_symlink("/proc/self/exe").parent_path().string() + "/stereoball-view";
  std::vector<std::string> args = {
      bin, "--port", "0", "--domain", std::to_string(o.domain), "--partition", partition};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = -1;
  if (posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ) != 0) return -1;
  posix_spawn_file_actions_destroy(&actions);
  for (int i = 0; i < 300 && port == 0; ++i) {
    std::this_thread::sleep_for(100ms);
    std::ifstream f(log);
    std::stringstream text;
    text << f.rdbuf();
    std::smatch m;
    const std::string s = text.str();
    if (std::regex_search(s, m, std::regex("viewer: http://127\\.0\\.0\\.1:(\\d+)/")))
      port = std::stoi(m[1]);
  }
  return pid;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(q * (v.size() - 1))];
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"stereoball bench viewer: CPU, latency and memory of stereoball view"};
  Options o;
  app.add_option("--width", o.width)->capture_default_str();
  app.add_option("--height", o.height)->capture_default_str();
  app.add_option("--rate", o.rate_hz, "frames per second")->capture_default_str();
  app.add_option("--phase-s", o.phase_s, "seconds per measurement")->capture_default_str();
  app.add_option("--loop-s", o.loop_s, "seconds of the connect/disconnect loop")
      ->capture_default_str();
  app.add_option("--domain", o.domain)->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  const std::string partition = "bench.viewer." + std::to_string(getpid());
  const std::string log = "/tmp/stereoball-bench-viewer-" + std::to_string(getpid()) + ".log";
  Publisher publisher(o, partition);
  int port = 0;
  const pid_t viewer = start_viewer(o, partition, log, port);
  if (viewer < 0 || port == 0) {
    std::fprintf(stderr, "bench viewer: the viewer did not start (see %s)\n", log.c_str());
    if (viewer > 0) kill(viewer, SIGTERM);
    return 1;
  }
  std::printf("stereo/frame %dx%d bgr8 at %.0f Hz, viewer pid %d on port %d\n", o.width, o.height,
              o.rate_hz, viewer, port);
  auto measure = [&](int clients) {
    std::vector<std::unique_ptr<sb::bench::PageClient>> page;
    for (int i = 0; i < clients; ++i) page.push_back(std::make_unique<sb::bench::PageClient>(port));
    std::this_thread::sleep_for(2s);  // reader created, first frames encoded
    const double cpu0 = cpu_s(viewer);
    uint64_t images0 = 0;
    for (auto& p : page) images0 += p->images();
    const auto t0 = std::chrono::steady_clock::now();
    std::this_thread::sleep_for(std::chrono::duration<double>(o.phase_s));
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu = (cpu_s(viewer) - cpu0) / wall * 100;
    uint64_t images = 0;
    std::vector<double> lat;
    for (auto& p : page) {
      images += p->images();
      auto l = p->latencies_ms();
      lat.insert(lat.end(), l.begin(), l.end());
    }
    const uint32_t readers = publisher.frame_readers();
    if (clients == 0) {
      std::printf("  0 clients: viewer CPU %5.1f %% of one core, stereo/frame readers %u\n", cpu,
                  readers);
    } else {
      std::printf(
          "  %d client(s): viewer CPU %5.1f %% of one core, %.1f images/s per client, latency "
          "capture->client p50 %.1f ms p95 %.1f ms, stereo/frame readers %u\n",
          clients, cpu, (images - images0) / wall / clients, percentile(lat, 0.5),
          percentile(lat, 0.95), readers);
    }
    page.clear();
    std::this_thread::sleep_for(1s);
  };
  std::printf("CPU and latency (%.0f s each):\n", o.phase_s);
  for (int clients : {0, 1, 2, 4, 0}) measure(clients);
  std::printf("10 clients connecting and disconnecting for %.0f s:\n", o.loop_s);
  const auto loop_end = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.loop_s);
  std::vector<double> rss;
  int rounds = 0;
  while (std::chrono::steady_clock::now() < loop_end) {
    {
      std::vector<std::unique_ptr<sb::bench::PageClient>> page;
      for (int i = 0; i < 10; ++i) page.push_back(std::make_unique<sb::bench::PageClient>(port));
      std::this_thread::sleep_for(1s);
    }
    ++rounds;
    std::this_thread::sleep_for(200ms);
    rss.push_back(rss_mb(viewer));
  }
  if (!rss.empty()) {
    const size_t tenth = std::max<size_t>(1, rss.size() / 10);
    double first = 0, last = 0;
    for (size_t i = 0; i < tenth; ++i) {
      first += rss[i] / tenth;
      last += rss[rss.size() - 1 - i] / tenth;
    }
    std::printf(
        "  %d rounds (%d connections): viewer RSS %.1f MB over the first tenth, %.1f MB "
        "over the last tenth, max %.1f MB\n",
        rounds, rounds * 10, first, last, *std::max_element(rss.begin(), rss.end()));
  }
  kill(viewer, SIGTERM);
  waitpid(viewer, nullptr, 0);
  return 0;
}
