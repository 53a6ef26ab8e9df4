// run_dds: camera_server (file source) and ball_detector as processes, as a user runs them.

#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

#include "child_process.hpp"
#include "common/dds/error.hpp"
#include "common/dds/participant.hpp"
#include "common/dds/reader.hpp"
#include "common/util/clock.hpp"
#include "common/util/install_layout.hpp"
#include "real_stereo_run.hpp"
#include "stereoball/topics.hpp"

namespace stereoball::real_stereo {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::int64_t wall_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// A temporary folder for the run (configs, the played pairs as links, the nodes' logs); removed
// unless kept for a report of what went wrong.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "stereoball-bench-real-stereo-XXXXXX");
    if (::mkdtemp(pattern.data())) path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    if (!path_.empty() && !keep_) fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  void keep() { keep_ = true; }

 private:
  std::string path_;
  bool keep_ = false;
};

Status write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  out.close();
  if (!out) return Error{path + ": cannot write"};
  return {};
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// The pairs of one play as links left/NNNNNN.ext, right/NNNNNN.ext in play order, so the file
// source's sorted globs give seq i = the i-th pair of the play.
Status link_pairs(const RealStereoSet& set, const std::vector<std::size_t>& rows,
                  const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir + "/left", ec);
  fs::create_directories(dir + "/right", ec);
  if (ec) return Error{dir + ": cannot create (" + ec.message() + ")"};
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const TruthRow& row = set.truth[rows[k]];
    char name[32];
    std::snprintf(name, sizeof name, "%06zu", k);
    const std::pair<std::string, std::string> eyes[] = {{"left", set.left_path(row)},
                                                        {"right", set.right_path(row)}};
    for (const auto& [eye, file] : eyes) {
      const fs::path target = fs::absolute(file, ec);
      const fs::path link = fs::path(dir) / eye / (name + fs::path(file).extension().string());
      fs::create_symlink(target, link, ec);
      if (ec) return Error{link.string() + ": cannot link to " + target.string()};
    }
  }
  return {};
}

std::string camera_config(const RealStereoSet& set, const std::string& play_dir,
                          const RunOptions& o, double rate_hz) {
  std::string y = "source: files\n";
  y += "left_glob: " + quoted(play_dir + "/left/*") + "\n";
  y += "right_glob: " + quoted(play_dir + "/right/*") + "\n";
  y += "width_px: " + std::to_string(set.image_size.width) + "\n";
  y += "height_px: " + std::to_string(set.image_size.height) + "\n";
  y += "rate_hz: " + std::to_string(rate_hz) + "\n";
  y += "loop: false\n";
  y += "calibration_file: " + quoted(fs::absolute(set.calibration_path).string()) + "\n";
  y += "frame_encoding: " + o.frame_encoding + "\n";
  y += "jpeg_quality: " + std::to_string(o.jpeg_quality) + "\n";
  y += "jpeg_chroma: " + quoted(o.jpeg_chroma) + "\n";
  y += "preview_max_width_px: 0\n";
  if (o.width_px != 0) y += "publish_width_px: " + std::to_string(o.width_px) + "\n";
  return y;
}

// One play of some pairs: what came back and what went wrong.
struct Play {
  std::map<std::size_t, Detection> got;        // row -> detection
  std::map<std::size_t, std::string> refused;  // row -> the node's status and reason
  std::vector<std::string> errors;             // the play as a whole
};

std::string format_hz(double hz) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f Hz", hz);
  return buf;
}

}  // namespace

RunResult run_dds(const RealStereoSet& set, const DetectorConfig& config,
                  const RunOptions& options) {
  RunResult out;
  out.mode = "dds";
  out.pairs.resize(set.truth.size());
  out.scale = options.width_px != 0 ? double(options.width_px) / double(set.image_size.width) : 1.0;
  out.played_size =
      options.width_px != 0
          ? cv::Size(options.width_px, int(std::lround(set.image_size.height * out.scale)))
          : set.image_size;
  auto fail = [&](const std::string& error) {
    out.errors.push_back(error);
    return out;
  };
  const auto stopped = [&] { return options.stop && options.stop->load(); };
  const std::string camera_bin = options.bin_dir + "/camera_server";
  const std::string detector_bin = options.bin_dir + "/ball_detector";
  for (const auto& b : {camera_bin, detector_bin}) {
    if (::access(b.c_str(), X_OK) != 0)
      return fail(b +
                  " not found: build it (cmake --build build --target camera_server "
                  "ball_detector) or give --bin-dir");
  }
  // Single host: loopback DDS unless the user chose a configuration.
  if (!std::getenv("CYCLONEDDS_URI")) {
    const std::string loopback = paths::shipped_config_path("cyclonedds/loopback.xml");
    std::error_code ec;
    if (!fs::is_regular_file(loopback, ec))
      return fail(
          "no Cyclone DDS configuration: set CYCLONEDDS_URI (shipped "
          "config/cyclonedds/loopback.xml not found at " +
          loopback + ")");
    ::setenv("CYCLONEDDS_URI", ("file://" + fs::absolute(loopback).string()).c_str(), 1);
    out.notes.push_back("DDS: " + loopback + " (CYCLONEDDS_URI was not set)");
  } else {
    out.notes.push_back(std::string("DDS: CYCLONEDDS_URI=") + std::getenv("CYCLONEDDS_URI"));
  }
  TempDir tmp;
  if (tmp.path().empty()) return fail("cannot create a temporary folder");
  const std::string partition = options.partition.empty()
                                    ? "bench-real-stereo-" + std::to_string(::getpid())
                                    : options.partition;
  const std::string detector_yaml = tmp.path() + "/ball_detector.yaml";
  if (auto st = write_file(detector_yaml, config.yaml); !st) return fail(st.error());
  const std::vector<std::string> dds_flags = {"--domain", std::to_string(options.domain),
                                              "--partition", partition};
  try {
    dds::DomainParticipant participant({options.domain, partition});
    dds::DataReader<stereoball_msg_BallDetection> detections(participant, topics::kBallDetection);
    std::vector<std::string> argv = {detector_bin, "--config", detector_yaml};
    argv.insert(argv.end(), dds_flags.begin(), dds_flags.end());
    auto detector = ChildProcess::start(argv, tmp.path() + "/ball_detector.log");
    if (!detector) return fail(detector.error());
    const auto node_failed = [&](ChildProcess& p, const std::string& what) {
      tmp.keep();
      return fail(p.name() + " " + what + " (exit " +
                  (p.exit_code() ? std::to_string(*p.exit_code()) : std::string("-")) +
                  "); its last lines (" + p.log_path() + "):\n" + p.log_tail(15));
    };
    // The detector is up once its ball/detection writer is seen.
    const auto start_deadline =
        Clock::now() + std::chrono::milliseconds(int(options.start_timeout_s * 1000));
    while (detections.matched_writers() == 0) {
      if (stopped()) return fail("interrupted");
      if (!detector->running()) return node_failed(*detector, "stopped before it was ready");
      if (Clock::now() > start_deadline)
        return node_failed(*detector, "was not seen on DDS within " +
                                          std::to_string(options.start_timeout_s) + " s");
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }

    // Plays the rows once; every pair answered, refused, or left for the retry. The play
    // starts with copies of its first pair (warm-up: the node's first frames of a calibration
    // also check the eye order, seconds at this size on a busy machine) whose answers are not
    // used, so the pairs themselves arrive at a detector that keeps up.
    double slowest_ms = 0;
    auto play = [&](const std::vector<std::size_t>& rows, double rate_hz, int attempt) -> Play {
      Play p;
      const std::string dir = tmp.path() + "/play" + std::to_string(attempt);
      const std::size_t warmup =
          std::max<std::size_t>(1, std::size_t(std::ceil(options.warmup_s * rate_hz)));
      std::vector<std::size_t> played(warmup, rows.front());
      played.insert(played.end(), rows.begin(), rows.end());
      if (auto st = link_pairs(set, played, dir); !st) {
        p.errors.push_back(st.error());
        return p;
      }
      const std::string cfg = dir + "/camera_server.yaml";
      if (auto st = write_file(cfg, camera_config(set, dir, options, rate_hz)); !st) {
        p.errors.push_back(st.error());
        return p;
      }
      for (auto& d : detections.take(SIZE_MAX)) (void)d;  // an earlier play's late answers
      // Frames of this play are stamped by camera_server from now on (wall clock).
      const std::int64_t play_start_ns = wall_ns();
      std::vector<std::string> cargv = {camera_bin, "--config", cfg};
      cargv.insert(cargv.end(), dds_flags.begin(), dds_flags.end());
      auto camera = ChildProcess::start(cargv, dir + "/camera_server.log");
      if (!camera) {
        p.errors.push_back(camera.error());
        return p;
      }
      const double play_s = double(played.size()) / rate_hz;
      const auto deadline =
          Clock::now() + std::chrono::milliseconds(int(
                             1000 * (options.start_timeout_s + play_s + options.pair_timeout_s)));
      // The detector works on the newest frame: once the last one is answered, every frame
      // before it has been answered or overwritten, and nothing more will come.
      bool last_answered = false;
      while (p.got.size() + p.refused.size() < rows.size() && !last_answered) {
        for (auto& d : detections.take(SIZE_MAX)) {
          if (d->capture_stamp_ns < play_start_ns) continue;
          if (d->frame_seq + 1 == played.size()) last_answered = true;
          if (d->frame_seq < warmup || d->frame_seq >= played.size()) continue;
          const std::size_t row = played[d->frame_seq];
          if (p.got.count(row) || p.refused.count(row)) continue;
          if (is_refusal(d->status)) {
            p.refused[row] =
                std::string(status_name(d->status)) + ": " + (d->reason ? d->reason : "");
          } else {
            p.got[row] = detection_from_message(*d);
            slowest_ms = std::max(slowest_ms, double(d->processing_ms));
          }
        }
        if (p.got.size() + p.refused.size() == rows.size() || last_answered) break;
        if (stopped()) {
          p.errors.push_back("interrupted");
          break;
        }
        if (!camera->running()) {
          tmp.keep();
          std::string hint;
          if (options.width_px != 0 && camera->log_contains("publish_width_px"))
            hint =
                "\n  (--width-px needs a camera_server that knows publish_width_px: "
                "width scaling, issue 38 item 4; this one refuses the key)";
          p.errors.push_back(
              "camera_server stopped (exit " + std::to_string(camera->exit_code().value_or(-1)) +
              "); its last lines (" + camera->log_path() + "):\n" + camera->log_tail(15) + hint);
          break;
        }
        if (!detector->running()) {
          tmp.keep();
          p.errors.push_back(
              "ball_detector stopped (exit " + std::to_string(detector->exit_code().value_or(-1)) +
              "); its last lines (" + detector->log_path() + "):\n" + detector->log_tail(15));
          break;
        }
        if (Clock::now() > deadline) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
      // camera_server has nothing left to do (loop: false).
      camera->stop(std::chrono::milliseconds(5000));
      return p;
    };

    std::vector<std::size_t> pending(set.truth.size());
    for (std::size_t i = 0; i < pending.size(); ++i) pending[i] = i;
    std::map<std::size_t, std::string> refused;
    bool run_stopped = false;
    const int attempts = options.retry ? 2 : 1;
    for (int attempt = 1; attempt <= attempts && !pending.empty(); ++attempt) {
      // A retry plays slower: the usual reason for a lost answer is a busy detector (at most
      // half the rate, and two of the slowest frames so far per frame).
      const double rate = attempt == 1
                              ? options.rate_hz
                              : std::min(options.rate_hz / 2,
                                         slowest_ms > 0 ? 500.0 / slowest_ms : options.rate_hz / 2);
      if (attempt > 1)
        out.notes.push_back("retry: " + std::to_string(pending.size()) +
                            " pair(s) without a detection played again at " + format_hz(rate));
      Play p = play(pending, rate, attempt);
      for (const auto& [row, det] : p.got) {
        out.pairs[row].detection = det;
        refused.erase(row);
      }
      for (const auto& [row, why] : p.refused) refused[row] = why;
      std::vector<std::size_t> still;
      for (std::size_t row : pending) {
        ++out.pairs[row].attempts;
        if (!out.pairs[row].detection) still.push_back(row);
      }
      pending = still;
      if (!p.errors.empty()) {
        run_stopped = true;
        for (auto& e : p.errors) out.errors.push_back(e);
        break;  // a node failed or the user stopped: retrying would fail the same way
      }
    }
    for (std::size_t row : pending) {
      const auto& t = set.truth[row];
      std::string e = "pair " + t.pair + " (" + t.left + "): no detection";
      if (refused.count(row)) {
        e = "pair " + t.pair + " (" + t.left + "): ball_detector refused it: " + refused[row];
        if (refused[row].find("image") != std::string::npos ||
            refused[row].find("limit") != std::string::npos ||
            refused[row].find("calibration") != std::string::npos)
          e += " (frames of " + std::to_string(out.played_size.width) + "x" +
               std::to_string(out.played_size.height) + " need the detector's image_limit at " +
               "least that: --image-limit WxH)";
      } else if (run_stopped) {
        e += " (the run stopped: see the error above)";
      } else {
        e += " after " + std::to_string(out.pairs[row].attempts) + " play(s)";
      }
      out.errors.push_back(e);
    }
    const int code = detector->stop(std::chrono::milliseconds(10000));
    if (code != 0 && !stopped()) {
      tmp.keep();
      out.errors.push_back("ball_detector exited with " + std::to_string(code) +
                           "; its last lines:\n" + detector->log_tail(15));
    }
  } catch (const dds::Error& e) {
    return fail(std::string("DDS: ") + e.what());
  }
  if (!out.errors.empty() && !stopped()) {
    tmp.keep();
    out.notes.push_back("the nodes' configurations and logs are kept in " + tmp.path());
  }
  return out;
}

}  // namespace stereoball::real_stereo
