// sb_rogue: an outsider on the deployment's domain and partition, for the attacker tests.
// It sends what would move the robot or change what it believes — cmd/velocity, cmd/estop
// releases, ball/track, ball/detection, stereo/calibration of another size — three ways:
//   --attack unsigned   no tag at all (what any Cyclone program sends)
//   --attack forged     signed with a key that is not the deployment's (--key-file)
//   --attack replay     captures the deployment's own authentic samples (CDR, as they travel)
//                       for --capture s, then sends them again at once and after the window
// It prints "rogue: sent N" when done. Only the test suite builds and runs it.

#include "common/util/cli11.hpp"

#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "common/dds/reader.hpp"
#include "common/dds/serialized.hpp"
#include "common/dds/writer.hpp"
#include "common/node/common_flags.hpp"

namespace sb = stereoball;
using namespace std::chrono_literals;

namespace {

struct Writers {
  explicit Writers(const sb::dds::DomainParticipant& p)
      : velocity(p, sb::topics::kVelocityCommand),
        estop(p, sb::topics::kEmergencyStop),
        track(p, sb::topics::kBallTrack),
        detection(p, sb::topics::kBallDetection),
        calibration(p, sb::topics::kStereoCalibration) {}
  sb::dds::DataWriter<stereoball_msg_VelocityCommand> velocity;
  sb::dds::DataWriter<stereoball_msg_EmergencyStop> estop;
  sb::dds::DataWriter<stereoball_msg_BallTrack> track;
  sb::dds::DataWriter<stereoball_msg_BallDetection> detection;
  sb::dds::DataWriter<stereoball_msg_StereoCalibration> calibration;
};

int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// Unsigned: forward() sends the sample with the all-zero tag it was built with.
template <typename W, typename T>
void send(W& writer, T& sample, bool sign) {
  if (sign) {
    writer.write(sample);
  } else {
    writer.forward(sample);
  }
}

// One of each hostile sample; sign = made with the rogue's own key.
size_t send_round(Writers& w, bool sign, uint64_t seq) {
  char source[] = "rogue";
  const int64_t t = now_ns();
  stereoball_msg_VelocityCommand v{};
  v.seq = seq;
  v.stamp_ns = t;
  v.linear_mps = 1.0;
  v.angular_radps = 0.5;
  v.source = source;
  send(w.velocity, v, sign);
  stereoball_msg_EmergencyStop e{};
  e.stamp_ns = t;
  e.engaged = false;
  e.reason = source;
  send(w.estop, e, sign);
  stereoball_msg_BallTrack tr{};
  tr.frame_seq = seq;
  tr.capture_stamp_ns = tr.publish_stamp_ns = tr.last_accepted_stamp_ns = t;
  tr.state = stereoball_msg_TRACK_FOLLOWING;
  tr.verdict = stereoball_msg_VERDICT_BLOCK_MATCH_ACCEPTED;
  tr.reason = source;
  tr.position_valid = true;
  tr.position_m[2] = 2.0;
  tr.distance_m = 2.0;
  tr.ssd = 0;
  send(w.track, tr, sign);
  stereoball_msg_BallDetection d{};
  d.frame_seq = seq;
  d.capture_stamp_ns = d.publish_stamp_ns = t;
  d.status = stereoball_msg_DETECTION_FOUND;
  d.reason = source;
  d.left = {320, 240, 20, 1};
  d.right = {300, 240, 20, 1};
  d.position_m[0] = 0.1;
  d.position_m[2] = 2.0;
  d.depth_from_size_m = 2.0;
  send(w.detection, d, sign);
  stereoball_msg_StereoCalibration c{};
  c.stamp_ns = t;
  c.width_px = 320;
  c.height_px = 240;
  c.k1[0] = c.k1[4] = c.k2[0] = c.k2[4] = 300;
  c.k1[8] = c.k2[8] = c.r[0] = c.r[4] = c.r[8] = 1;
  c.t[0] = -0.1;
  c.source = source;
  send(w.calibration, c, sign);
  return 5;
}

int run_direct(const sb::dds::DomainParticipant& p, bool sign, double duration_s, double rate_hz) {
  Writers w(p);
  std::this_thread::sleep_for(2s);  // discovery
  // How many of the deployment's readers took the rogue in: discovery did not keep it out.
  std::printf("rogue: matched %u readers\n",
              w.velocity.matched_readers() + w.estop.matched_readers() + w.track.matched_readers() +
                  w.detection.matched_readers() + w.calibration.matched_readers());
  std::fflush(stdout);
  size_t sent = 0;
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(duration_s);
  for (uint64_t seq = 0; std::chrono::steady_clock::now() < until; ++seq) {
    sent += send_round(w, sign, seq);
    std::this_thread::sleep_for(std::chrono::duration<double>(1.0 / rate_hz));
  }
  std::printf("rogue: sent %zu\n", sent);
  return 0;
}

int run_replay(const sb::dds::DomainParticipant& p, double capture_s, double duration_s,
               double window_s) {
  // Capture the authentic samples exactly as they travel; resend the same bytes.
  const sb::topics::TopicSpec* specs[] = {
      &sb::topics::kVelocityCommand.spec, &sb::topics::kEmergencyStop.spec,
      &sb::topics::kBallTrack.spec, &sb::topics::kBallDetection.spec,
      &sb::topics::kStereoCalibration.spec};
  std::vector<std::unique_ptr<sb::dds::SerializedReader>> readers;
  std::vector<std::unique_ptr<sb::dds::SerializedWriter>> writers;
  for (const auto* spec : specs) {
    readers.push_back(std::make_unique<sb::dds::SerializedReader>(p, *spec));
    writers.push_back(std::make_unique<sb::dds::SerializedWriter>(p, *spec));
  }
  std::vector<std::vector<sb::dds::SerializedSample>> captured(readers.size());
  const auto capture_end =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(capture_s);
  while (std::chrono::steady_clock::now() < capture_end) {
    for (size_t i = 0; i < readers.size(); ++i) readers[i]->take(captured[i]);
    std::this_thread::sleep_for(20ms);
  }
  size_t total = 0;
  for (const auto& c : captured) total += c.size();
  std::printf("rogue: captured %zu\n", total);
  size_t sent = 0;
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(duration_s);
  while (std::chrono::steady_clock::now() < until) {
    for (size_t i = 0; i < writers.size(); ++i) {
      for (const auto& s : captured[i]) {
        writers[i]->write(s.cdr);
        ++sent;
        // Spaced out, so keep-last-1 readers check each one instead of only the last.
        std::this_thread::sleep_for(2ms);
      }
    }
    // Once inside the freshness window, then again after it.
    std::this_thread::sleep_for(std::chrono::duration<double>(window_s));
  }
  std::printf("rogue: sent %zu\n", sent);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"sb_rogue: hostile publisher for the attacker tests (unsigned|forged|replay)"};
  sb::node::CommonOptions common;
  sb::node::add_common_flags(app, common, "", false);
  std::string attack = "unsigned";
  double duration_s = 4, rate_hz = 20, capture_s = 3, window_s = 1.2;
  app.add_option("--attack", attack)->check(CLI::IsMember({"unsigned", "forged", "replay"}));
  app.add_option("--duration", duration_s, "seconds of sending");
  app.add_option("--rate", rate_hz, "rounds per second (unsigned, forged)");
  app.add_option("--capture", capture_s, "seconds of capture before replaying");
  app.add_option("--replay-period", window_s, "seconds between replays of the capture");
  CLI11_PARSE(app, argc, argv);
  try {
    sb::dds::DomainParticipant p({common.domain_id, common.partition, common.key_file});
    std::printf("rogue: %s on domain %d\n", attack.c_str(), common.domain_id);
    std::fflush(stdout);
    if (attack == "replay") return run_replay(p, capture_s, duration_s, window_s);
    return run_direct(p, attack == "forged", duration_s, rate_hz);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sb_rogue: %s\n", e.what());
    return 1;
  }
}
