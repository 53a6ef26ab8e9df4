// sb_netns_observer: subscribes the system's topics and prints one line per sample with its
// receive time (see observer_log.hpp), for the two-host test and benchmark. Runs inside a
// namespace via `ip netns exec`; stops on SIGTERM or after --duration.

#include "common/util/cli11.hpp"

#include <cstdio>
#include <exception>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "common/dds/reader.hpp"
#include "common/node/common_flags.hpp"
#include "common/node/node_runner.hpp"
#include "stereoball/topics.hpp"

namespace sb = stereoball;

namespace {

const char* text(const char* s) {
  return s ? s : "?";
}

// Subscriptions chosen by --topics; each prints its samples as they arrive.
struct Observer {
  explicit Observer(sb::node::Runner& runner, const std::set<std::string>& topics) {
    auto& p = runner.participant();
    if (topics.count("frame")) {
      frames.emplace(p, sb::topics::kStereoFrame);
      runner.on_data(frames->handle(), [this] { on_frames(); });
    }
    if (topics.count("truth")) {
      truths.emplace(p, sb::topics::kGroundTruth);
      runner.on_data(truths->handle(), [this] { on_truths(); });
    }
    if (topics.count("detection")) {
      detections.emplace(p, sb::topics::kBallDetection);
      runner.on_data(detections->handle(), [this] { on_detections(); });
    }
    if (topics.count("track")) {
      tracks.emplace(p, sb::topics::kBallTrack);
      runner.on_data(tracks->handle(), [this] { on_tracks(); });
    }
    if (topics.count("cmd")) {
      commands.emplace(p, sb::topics::kVelocityCommand);
      runner.on_data(commands->handle(), [this] { on_commands(); });
    }
  }

  void on_frames() {
    auto loaned = frames->take_loaned();
    const int64_t rx = sb::node::now_ns();
    for (size_t i = 0; i < loaned.size(); ++i) {
      if (!loaned.valid(i)) continue;
      const auto& f = loaned[i];
      std::printf("F %lld %lld %llu %llu %s\n", (long long)rx, (long long)f.stamp_ns,
                  (unsigned long long)f.seq,
                  (unsigned long long)(f.left.data._length + f.right.data._length),
                  text(f.encoding));
    }
  }
  void on_truths() {
    for (auto& s : truths->take(64)) {
      const auto& g = *s;
      std::printf("G %lld %lld %llu %.4f %.4f %.4f %.4f %.4f %.4f %.4f\n",
                  (long long)sb::node::now_ns(), (long long)g.stamp_ns,
                  (unsigned long long)g.frame_seq, g.robot_x_m, g.robot_y_m, g.robot_yaw_rad,
                  g.robot_linear_mps, g.robot_angular_radps, g.ball_world_m[0], g.ball_world_m[1]);
    }
  }
  void on_detections() {
    for (auto& s : detections->take(64)) {
      std::printf("D %lld %lld %lld %llu %d %.4f\n", (long long)sb::node::now_ns(),
                  (long long)s->capture_stamp_ns, (long long)s->publish_stamp_ns,
                  (unsigned long long)s->frame_seq, (int)s->status, s->processing_ms);
    }
  }
  void on_tracks() {
    for (auto& s : tracks->take(64)) {
      std::printf("T %lld %lld %lld %llu %d %.4f %.4f\n", (long long)sb::node::now_ns(),
                  (long long)s->capture_stamp_ns, (long long)s->publish_stamp_ns,
                  (unsigned long long)s->frame_seq, (int)s->state, s->distance_m, s->bearing_rad);
    }
  }
  void on_commands() {
    for (auto& s : commands->take(64)) {
      std::printf("C %lld %lld %llu %.4f %.4f %lld\n", (long long)sb::node::now_ns(),
                  (long long)s->stamp_ns, (unsigned long long)s->seq, s->linear_mps,
                  s->angular_radps, (long long)s->capture_stamp_ns);
    }
  }

  std::optional<sb::dds::DataReader<stereoball_msg_StereoFrame>> frames;
  std::optional<sb::dds::DataReader<stereoball_msg_GroundTruth>> truths;
  std::optional<sb::dds::DataReader<stereoball_msg_BallDetection>> detections;
  std::optional<sb::dds::DataReader<stereoball_msg_BallTrack>> tracks;
  std::optional<sb::dds::DataReader<stereoball_msg_VelocityCommand>> commands;
};

}  // namespace

int main(int argc, char** argv) {
  sb::node::block_termination_signals();
  CLI::App app{
      "sb_netns_observer: print every sample of the chosen topics with its receive time, one\n"
      "line each (format in tests/distributed/observer_log.hpp)"};
  sb::node::CommonOptions common;
  sb::node::add_common_flags(app, common, "", false);
  std::vector<std::string> topics{"truth", "track", "cmd"};
  double duration_s = 0;
  app.add_option("--topics", topics, "any of: frame truth detection track cmd")
      ->check(CLI::IsMember({"frame", "truth", "detection", "track", "cmd"}))
      ->capture_default_str();
  app.add_option("--duration", duration_s, "stop after S seconds (0 = until SIGTERM)")
      ->check(CLI::NonNegativeNumber);
  CLI11_PARSE(app, argc, argv);
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // whole lines reach the reader promptly
  try {
    sb::node::Runner runner("netns_observer", common);
    runner.set_heartbeat_period(0);
    Observer observer(runner, std::set<std::string>(topics.begin(), topics.end()));
    if (duration_s > 0) {
      runner.every(static_cast<int64_t>(duration_s * 1e9), [&](int64_t) { runner.stop(); });
    }
    std::printf("# observing\n");
    return runner.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sb_netns_observer: %s\n", e.what());
    return 1;
  }
}
