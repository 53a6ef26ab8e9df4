// run_flood and run_rogue: the faults a chaos run starts as child processes in the robot
// namespace, publishing on the deployment's domain like any other program there could.
#include "chaos_children.hpp"

#include <chrono>
#include <cstdio>
#include <iterator>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "chaos_processes.hpp"
#include "common/dds/writer.hpp"
#include "stereoball/topics.hpp"

namespace sb = stereoball;

namespace stereoball::bench_chaos {

int run_flood(const Options& o) {
  // With the deployment's key (from STEREOBALL_KEY_FILE) only to use the LAN: stereo/frame is
  // not authenticated, so anything on the network can publish frames like these.
  sb::dds::DomainParticipant participant({o.domain, o.partition});
  sb::dds::DataWriter<stereoball_msg_StereoFrame> writer(participant, sb::topics::kStereoFrame);
  std::mt19937_64 rng(o.seed);
  const char* encodings[] = {"bgr8", "jpeg", "png", "mono8", "yuyv", "", "bgr8\x01x"};
  std::vector<uint8_t> left, right;
  const int64_t until = now_ns() + static_cast<int64_t>(o.child_seconds * 1e9);
  uint64_t sent = 0;
  while (!g_stop && now_ns() < until) {
    // Sizes that lie about the data, data that is not an image, stamps anywhere.
    left.resize(rng() % 70'000);
    right.resize(rng() % 4 == 0 ? left.size() : rng() % 70'000);
    for (auto& b : left) b = static_cast<uint8_t>(rng());
    for (auto& b : right) b = static_cast<uint8_t>(rng());
    if (rng() % 3 == 0 && left.size() > 4) {  // a JPEG or PNG signature in front of garbage
      left[0] = 0xff, left[1] = 0xd8, left[2] = 0xff, left[3] = 0xe0;
    }
    stereoball_msg_StereoFrame f{};
    f.seq = rng();
    f.stamp_ns = rng() % 2 ? now_ns() : static_cast<int64_t>(rng());
    std::string source = "chaos-flood";
    f.source = source.data();
    f.encoding = const_cast<char*>(encodings[rng() % std::size(encodings)]);
    f.rectified = rng() % 2;
    for (auto* eye : {&f.left, &f.right}) {
      eye->capture_stamp_ns = rng() % 2 ? f.stamp_ns : static_cast<int64_t>(rng());
      eye->width_px = rng() % 4 ? 640 : static_cast<uint32_t>(rng() % 100'000);
      eye->height_px = rng() % 4 ? 480 : static_cast<uint32_t>(rng() % 100'000);
      eye->step_bytes = rng() % 2 ? eye->width_px * 3 : static_cast<uint32_t>(rng());
    }
    f.left.data._buffer = left.data();
    f.left.data._length = f.left.data._maximum = static_cast<uint32_t>(left.size());
    f.right.data._buffer = right.data();
    f.right.data._length = f.right.data._maximum = static_cast<uint32_t>(right.size());
    writer.write(f, now_ns());
    ++sent;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::printf("flood: %llu garbage frames sent\n", static_cast<unsigned long long>(sent));
  return 0;
}

int run_rogue(const Options& o) {
  // The key file comes from STEREOBALL_KEY_FILE: a key the deployment does not know.
  sb::dds::DomainParticipant participant({o.domain, o.partition});
  sb::dds::DataWriter<stereoball_msg_VelocityCommand> writer(participant,
                                                             sb::topics::kVelocityCommand);
  const int64_t until = now_ns() + static_cast<int64_t>(o.child_seconds * 1e9);
  uint64_t sent = 0;
  std::string source = "chaos-rogue";
  while (!g_stop && now_ns() < until) {
    stereoball_msg_VelocityCommand c{};
    c.seq = kRogueSeqBase + sent;
    c.stamp_ns = now_ns();
    c.linear_mps = 0.9;
    c.angular_radps = -1.7;
    c.source = source.data();
    writer.write(c);
    ++sent;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::printf("rogue: %llu commands sent\n", static_cast<unsigned long long>(sent));
  return 0;
}

}  // namespace stereoball::bench_chaos
