// stereoball bench auth: what message authentication costs.
//  1. Per sample: sign (canonical encoding + HMAC-SHA-512-256) and verify (the same plus the
//     replay check) for one sample of each authenticated topic, thread CPU µs, median of runs.
//  2. Per hop: round trip of cmd/velocity between two participants of this process over
//     loopback (A writes, B echoes, A takes), keyed vs keyless side by side, median µs.

#include "common/util/cli11.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>
#include <vector>

#include "common/auth/key_file.hpp"
#include "common/dds/auth_session.hpp"
#include "common/dds/reader.hpp"
#include "common/dds/writer.hpp"
#include "common/util/bench_clock.hpp"

namespace sb = stereoball;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

// Median over runs of the per-call thread CPU time of f, µs.
template <typename F>
double per_call_us(int runs, int calls, F&& f) {
  std::vector<double> us;
  for (int r = 0; r < runs; ++r) {
    const double t0 = sb::bench::thread_cpu_ms();
    for (int i = 0; i < calls; ++i) f();
    us.push_back((sb::bench::thread_cpu_ms() - t0) * 1e3 / calls);
  }
  return median(us);
}

template <typename T>
void bench_topic(sb::dds::AuthSession& session, const sb::topics::Topic<T>& topic, T sample,
                 int runs, int calls) {
  sb::auth::LinkClock clock(sb::auth::random_link_id());
  const double sign_us =
      per_call_us(runs, calls, [&] { session.sign(topic.spec, clock, sample.auth, &sample); });
  const size_t bytes = sb::dds::canonical_encoding(topic.spec.descriptor, &sample).size();
  // Verify the same signed sample each time with a fresh guard (the MAC is the cost).
  const double verify_us = per_call_us(runs, calls, [&] {
    auto guard = session.make_guard(topic.spec);
    session.verify(topic.spec, guard, sample.auth, &sample);
  });
  std::printf("  %-20s %6zu B   sign %6.2f us   verify %6.2f us\n",
              std::string(topic.spec.name).c_str(), bytes, sign_us, verify_us);
}

// Median round trip (µs) of cmd/velocity A -> B -> A on one domain with the given key file.
double round_trip_us(int domain, const std::string& key_file, int count) {
  sb::dds::DomainParticipant a({domain, "bench.a", key_file});
  sb::dds::DomainParticipant b({domain, "bench.b", key_file});
  // A writes in partition bench.a... B reads there and answers in bench.b.
  sb::dds::DomainParticipant a_in({domain, "bench.b", key_file});
  sb::dds::DomainParticipant b_in({domain, "bench.a", key_file});
  sb::dds::DataWriter<stereoball_msg_VelocityCommand> ping(a, sb::topics::kVelocityCommand);
  sb::dds::DataReader<stereoball_msg_VelocityCommand> ping_in(b_in, sb::topics::kVelocityCommand);
  sb::dds::DataWriter<stereoball_msg_VelocityCommand> pong(b, sb::topics::kVelocityCommand);
  sb::dds::DataReader<stereoball_msg_VelocityCommand> pong_in(a_in, sb::topics::kVelocityCommand);
  ping.wait_for_readers(1, 5'000'000'000);
  pong.wait_for_readers(1, 5'000'000'000);
  std::vector<double> us;
  char source[] = "bench";
  for (int i = 0; i < count; ++i) {
    stereoball_msg_VelocityCommand cmd{};
    cmd.seq = static_cast<uint64_t>(i);
    cmd.source = source;
    const double t0 = sb::bench::wall_ms();
    ping.write(cmd);
    bool back = false;
    while (!back && sb::bench::wall_ms() - t0 < 1000) {
      for (auto& s : ping_in.take()) pong.write(*s);
      back = !pong_in.take().empty();
    }
    if (back) us.push_back((sb::bench::wall_ms() - t0) * 1e3);
  }
  return median(us);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"stereoball bench auth: cost of message authentication per sample and per hop"};
  int runs = 5, calls = 2000, trips = 300, domain = 0;
  app.add_option("--runs", runs, "repetitions (median)")->capture_default_str();
  app.add_option("--calls", calls, "sign/verify calls per repetition")->capture_default_str();
  app.add_option("--trips", trips, "round trips per configuration")->capture_default_str();
  app.add_option("--domain", domain, "first of two DDS domains used for the round trips")
      ->check(CLI::Range(0, 231))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  const std::string dir = std::filesystem::temp_directory_path() / "sb_bench_auth";
  std::filesystem::create_directories(dir);
  const std::string key = dir + "/bench.key";
  if (auto e = sb::auth::save_key_file(key, sb::auth::new_keyring()); !e) {
    std::fprintf(stderr, "bench auth: %s\n", e.error().c_str());
    return 1;
  }
  sb::dds::AuthSession session(key);
  std::printf("per sample (thread CPU, median of %d x %d calls):\n", runs, calls);
  bench_topic(session, sb::topics::kVelocityCommand, stereoball_msg_VelocityCommand{}, runs, calls);
  bench_topic(session, sb::topics::kEmergencyStop, stereoball_msg_EmergencyStop{}, runs, calls);
  bench_topic(session, sb::topics::kBallTrack, stereoball_msg_BallTrack{}, runs, calls);
  bench_topic(session, sb::topics::kBallDetection, stereoball_msg_BallDetection{}, runs, calls);
  stereoball_msg_StereoCalibration calibration{};
  double d[5] = {0.1, 0.01, 0, 0, 0.001};
  calibration.d1 = {5, 5, d, false};
  calibration.d2 = {5, 5, d, false};
  bench_topic(session, sb::topics::kStereoCalibration, calibration, runs, calls);
  // Frames are not authenticated; what it would cost for a raw 640x480 bgr8 pair.
  const std::vector<uint8_t> frame(640 * 480 * 3 * 2, 0x5a);
  const sb::auth::Key frame_key = sb::auth::random_key();
  const double frame_us = per_call_us(runs, 20, [&] {
    const auto mac = sb::auth::compute_mac(frame_key, "stereo/frame", frame);
    (void)mac;
  });
  std::printf("  %-20s %6zu B   MAC    %6.0f us   (not authenticated; for comparison)\n",
              "stereo/frame bgr8", frame.size(), frame_us);

  // Keyed and keyless on separate domains (a keyless participant has its own loopback-only
  // domain configuration), alternated so load changes hit both alike.
  std::vector<double> keyed, keyless;
  for (int r = 0; r < 3; ++r) {
    keyless.push_back(round_trip_us(domain, "", trips));
    keyed.push_back(round_trip_us(domain + 1, key, trips));
  }
  const double k = median(keyed), n = median(keyless);
  std::printf(
      "cmd/velocity round trip A->B->A, loopback, median of 3 x %d (2 signs + 2 checks):\n"
      "  keyless %.1f us   keyed %.1f us   difference %+.1f us (%+.1f %%)\n",
      trips, n, k, k - n, n > 0 ? 100.0 * (k - n) / n : 0.0);
  std::filesystem::remove_all(dir);
  return 0;
}
