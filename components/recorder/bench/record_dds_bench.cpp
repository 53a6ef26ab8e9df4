// End-to-end recording benchmark: publishes simulated 640x480 bgr8 stereo frames at 60 Hz plus
// detections, tracks, commands and ground truth at 60 Hz over DDS, while a real
// `stereoball-record --all` process records them. Prints frames published vs recorded, drops,
// MB/s, and the recorder's CPU per MB (from wait4 rusage).
//   recorder_dds_bench [--seconds S] [--dir DIR] [--domain N] [--keep] [-- extra stereoball-record
//   flags]

#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "common/dds/writer.hpp"
#include "common/node/node_runner.hpp"
#include "recorder/core/file_info.hpp"
#include "recorder/io/file_io.hpp"

namespace sb = stereoball;

namespace {

int die(const std::string& what) {
  std::fprintf(stderr, "recorder_dds_bench: %s\n", what.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  double seconds = 10;
  std::string dir = "/tmp";
  int domain = sb::dds::domain_from_env(0);
  std::vector<std::string> extra;
  bool keep = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--seconds" && i + 1 < argc)
      seconds = std::stod(argv[++i]);
    else if (a == "--dir" && i + 1 < argc)
      dir = argv[++i];
    else if (a == "--keep")
      keep = true;
    else if (a == "--domain" && i + 1 < argc)
      domain = std::stoi(argv[++i]);
    else if (a == "--") {
      for (++i; i < argc; ++i) extra.push_back(argv[i]);
    } else
      return die(
          "usage: recorder_dds_bench [--seconds S] [--dir DIR] [--domain N] [--keep] [-- flags]");
  }
  const std::string partition = "recorder_bench_" + std::to_string(getpid());
  const std::string file = dir + "/recorder_dds_bench.mcap";
  const std::string recorder = std::string(SB_BIN_DIR) + "/stereoball-record";
  std::vector<std::string> args = {
      recorder,      "--all",  "-q", "-o", file, "--domain", std::to_string(domain),
      "--partition", partition};
  args.insert(args.end(), extra.begin(), extra.end());

  const pid_t child = fork();
  if (child < 0) return die("fork failed");
  if (child == 0) {
    std::vector<char*> cargs;
    for (auto& s : args) cargs.push_back(s.data());
    cargs.push_back(nullptr);
    execv(cargs[0], cargs.data());
    std::fprintf(stderr, "recorder_dds_bench: cannot run %s\n", cargs[0]);
    _exit(127);
  }

  sb::dds::DomainParticipant participant({domain, partition});
  // Reliable frames for the benchmark, so a lost frame is the recorder's, not the transport's.
  auto frame_qos = sb::topics::kStereoFrame.spec.qos;
  frame_qos.reliability = sb::topics::Reliability::kReliable;
  frame_qos.history_depth = 4;
  sb::dds::DataWriter<stereoball_msg_StereoFrame> frames(participant, sb::topics::kStereoFrame,
                                                         frame_qos);
  sb::dds::DataWriter<stereoball_msg_BallDetection> detections(participant,
                                                               sb::topics::kBallDetection);
  sb::dds::DataWriter<stereoball_msg_BallTrack> tracks(participant, sb::topics::kBallTrack);
  sb::dds::DataWriter<stereoball_msg_VelocityCommand> commands(participant,
                                                               sb::topics::kVelocityCommand);
  sb::dds::DataWriter<stereoball_msg_GroundTruth> truth(participant, sb::topics::kGroundTruth);
  if (!frames.wait_for_readers(1, 15'000'000'000) || !truth.wait_for_readers(1, 5'000'000'000)) {
    kill(child, SIGKILL);
    return die("the recorder did not subscribe within 15 s");
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));

  constexpr uint32_t kW = 640, kH = 480;
  std::vector<uint8_t> left(kW * kH * 3), right(kW * kH * 3);
  for (size_t i = 0; i < left.size(); ++i) {
    left[i] = static_cast<uint8_t>((i * 7) ^ (i >> 9));
    right[i] = static_cast<uint8_t>((i * 5) ^ (i >> 8));
  }
  char source[] = "bench", encoding[] = "bgr8", empty[] = "";
  const int count = static_cast<int>(seconds * 60);
  const int64_t period = 16'666'667;
  int64_t next = sb::node::monotonic_ns();
  for (int k = 0; k < count; ++k) {
    stereoball_msg_StereoFrame f{};
    f.seq = static_cast<uint64_t>(k);
    f.stamp_ns = sb::node::now_ns();
    f.source = source;
    f.encoding = encoding;
    for (auto* eye : {&f.left, &f.right}) {
      eye->width_px = kW;
      eye->height_px = kH;
      eye->step_bytes = kW * 3;
      auto& img = eye == &f.left ? left : right;
      img[k % img.size()] ^= 1;  // every frame differs
      eye->data = {static_cast<uint32_t>(img.size()), static_cast<uint32_t>(img.size()), img.data(),
                   false};
    }
    frames.write(f);
    stereoball_msg_BallDetection d{};
    d.frame_seq = f.seq;
    d.reason = empty;
    detections.write(d);
    stereoball_msg_BallTrack t{};
    t.frame_seq = f.seq;
    t.reason = empty;
    tracks.write(t);
    stereoball_msg_VelocityCommand c{};
    c.seq = f.seq;
    c.source = source;
    commands.write(c);
    stereoball_msg_GroundTruth g{};
    g.frame_seq = f.seq;
    g.scenario = empty;
    truth.write(g);
    next += period;
    std::this_thread::sleep_for(std::chrono::nanoseconds(next - sb::node::monotonic_ns()));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  kill(child, SIGINT);
  int status = 0;
  rusage usage{};
  wait4(child, &status, 0, &usage);
  const double cpu_s = usage.ru_utime.tv_sec + usage.ru_stime.tv_sec +
                       1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);

  auto src = sb::recorder::FileSource::open(file);
  if (!src) return die(src.error());
  auto info = sb::recorder::collect_file_info(**src);
  if (!info) return die(info.error());
  uint64_t recorded_frames = 0, payload = 0;
  for (const auto& t : info->topics) {
    if (t.topic == "stereo/frame") recorded_frames = t.messages;
    payload += t.bytes;
  }
  const double mb = payload / 1e6;
  std::printf("published %d stereo frames (640x480 bgr8 x2) + 4 other topics at 60 Hz for %.1f s\n",
              count, seconds);
  std::printf("recorder exit %d, frames recorded %llu (%llu missing), file complete: %s\n",
              WIFEXITED(status) ? WEXITSTATUS(status) : -1,
              static_cast<unsigned long long>(recorded_frames),
              static_cast<unsigned long long>(count - recorded_frames),
              info->complete ? "yes" : "no");
  std::printf(
      "recorded %.1f MB payload: %.1f MB/s over the publishing time, recorder CPU %.1f s "
      "= %.2f ms/MB (%.0f%% of one core)\n",
      mb, mb / seconds, cpu_s, 1e3 * cpu_s / mb, 100.0 * cpu_s / (seconds + 2));
  if (keep)
    std::printf("kept %s\n", file.c_str());
  else
    std::remove(file.c_str());
  return 0;
}
