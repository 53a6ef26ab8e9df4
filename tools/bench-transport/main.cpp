// stereoball bench transport: latency and throughput of a 640x480 stereo frame between two
// processes on this host, side by side in the same run with Cyclone's own ddsperf for the
// same serialized sample size, reliability, ping-pong mode and Cyclone configuration
// (like_for_like.hpp); what still differs is printed under the table. Prints figures; asserts
// nothing.
//
// Latency is half the round trip (ping -> pong -> ping), the definition ddsperf's ping uses.

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include "common/util/cli11.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "common/dds/reader.hpp"
#include "common/dds/serialized.hpp"
#include "common/dds/waitset.hpp"
#include "common/dds/writer.hpp"
#include "common/node/node_runner.hpp"
#include "common/util/deployment.hpp"
#include "ddsperf_log.hpp"
#include "like_for_like.hpp"

namespace sb = stereoball;
namespace bt = stereoball::bench_transport;

namespace {

bool g_reliable = false;
// ddsperf's sample size (our serialized StereoFrame) and its environment (our Cyclone
// configuration), set once in main.
size_t g_ddsperf_sample_bytes = 0;
std::vector<std::string> g_ddsperf_env;

// The frame topic's QoS, or the same made reliable (--reliable) to compare like with like.
sb::topics::QosSpec frame_qos() {
  auto qos = sb::topics::kStereoFrame.spec.qos;
  if (g_reliable) qos.reliability = sb::topics::Reliability::kReliable;
  return qos;
}

constexpr uint32_t kWidth = 640, kHeight = 480;
constexpr int64_t kSecond = 1'000'000'000;

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t i = std::min(v.size() - 1, static_cast<size_t>(p / 100.0 * (v.size() - 1) + 0.5));
  return v[i];
}

double median(std::vector<double> v) {
  return percentile(std::move(v), 50);
}

struct Frame {
  std::vector<uint8_t> left, right;
  stereoball_msg_StereoFrame msg{};
  Frame() : left(kWidth * kHeight * 3, 7), right(kWidth * kHeight * 3, 9) {
    msg.source = const_cast<char*>("bench");
    msg.encoding = const_cast<char*>("bgr8");
    for (auto* eye : {&msg.left, &msg.right}) {
      eye->width_px = kWidth;
      eye->height_px = kHeight;
      eye->step_bytes = kWidth * 3;
    }
    msg.left.data = {static_cast<uint32_t>(left.size()), static_cast<uint32_t>(left.size()),
                     left.data(), false};
    msg.right.data = {static_cast<uint32_t>(right.size()), static_cast<uint32_t>(right.size()),
                      right.data(), false};
  }
};

// Waits until reader has data or timeout; true if data.
bool wait_data(sb::dds::WaitSet& ws, int64_t timeout_ns) {
  return !ws.wait(timeout_ns).empty();
}

int run_pong(int domain, const std::string& partition, double seconds) {
  sb::dds::DomainParticipant in({domain, partition + ".ping"});
  sb::dds::DomainParticipant out({domain, partition + ".pong"});
  sb::dds::DataReader<stereoball_msg_StereoFrame> reader(in, sb::topics::kStereoFrame, frame_qos());
  sb::dds::DataWriter<stereoball_msg_StereoFrame> writer(out, sb::topics::kStereoFrame,
                                                         frame_qos());
  sb::dds::WaitSet ws(in);
  sb::dds::ReadCondition cond(reader.handle());
  ws.attach(cond.handle(), 1);
  const int64_t end = sb::node::monotonic_ns() + static_cast<int64_t>(seconds * kSecond);
  while (sb::node::monotonic_ns() < end) {
    if (!wait_data(ws, 100'000'000)) continue;
    auto samples = reader.take_loaned();
    for (size_t i = 0; i < samples.size(); ++i) {
      if (samples.valid(i)) writer.write(samples[i], samples.info(i).source_timestamp);
    }
  }
  return 0;
}

struct Figures {
  double median_us = 0, p99_us = 0, rate_hz = 0, mbps = 0;
  size_t count = 0;
  double overall_p99_us = 0;  // ours only: p99 over all samples (ddsperf prints per second)
  // What the figures above are made of, so slices of one run can be pooled.
  std::vector<double> second_medians_us, second_p99s_us;
  std::vector<double> all_us;  // ours only
};

// One run's slices of one side pooled: the per-second percentiles of every slice together,
// median over the seconds, as for a single slice.
Figures pooled(const std::vector<Figures>& slices) {
  Figures f;
  double seconds = 0;
  for (const Figures& s : slices) {
    f.second_medians_us.insert(f.second_medians_us.end(), s.second_medians_us.begin(),
                               s.second_medians_us.end());
    f.second_p99s_us.insert(f.second_p99s_us.end(), s.second_p99s_us.begin(),
                            s.second_p99s_us.end());
    f.all_us.insert(f.all_us.end(), s.all_us.begin(), s.all_us.end());
    f.count += s.count;
    if (s.rate_hz > 0) seconds += static_cast<double>(s.count) / s.rate_hz;
  }
  if (f.second_medians_us.empty()) return f;
  f.median_us = median(f.second_medians_us);
  f.p99_us = median(f.second_p99s_us);
  f.overall_p99_us = percentile(f.all_us, 99);
  f.rate_hz = seconds > 0 ? static_cast<double>(f.count) / seconds : 0;
  f.mbps = f.rate_hz * static_cast<double>(g_ddsperf_sample_bytes) / 1e6;
  return f;
}

// ddsperf prints a 50 % and 99 % line per second of pinging; ours are summarised the same
// way (per-second percentiles, median over the seconds), so the ratio compares like with like.
// Earlier runs compared our p99 over all samples with the median of ddsperf's per-second p99s:
// one slow second moved ours and not theirs (ratio 1.60 in one run, 0.97 in another).
struct Sample {
  int64_t sent_ns;
  double half_rtt_us;
};
Figures per_second_figures(const std::vector<Sample>& samples) {
  Figures f;
  if (samples.empty()) return f;
  std::vector<double> medians, p99s, all;
  std::vector<double> second;
  int64_t second_start = samples.front().sent_ns;
  auto close_second = [&] {
    if (second.size() >= bt::kMinSamplesPerSecond) {  // else no meaningful 99th percentile
      medians.push_back(median(second));
      p99s.push_back(percentile(second, 99));
    }
    second.clear();
  };
  for (const auto& s : samples) {
    if (s.sent_ns - second_start >= kSecond) {
      close_second();
      second_start = s.sent_ns;
    }
    second.push_back(s.half_rtt_us);
    all.push_back(s.half_rtt_us);
  }
  close_second();
  f.count = samples.size();
  f.median_us = median(medians);
  f.p99_us = median(p99s);
  f.overall_p99_us = percentile(all, 99);
  f.second_medians_us = std::move(medians);
  f.second_p99s_us = std::move(p99s);
  f.all_us = std::move(all);
  return f;
}

Figures run_ping(int domain, const std::string& partition, int frames, double min_seconds) {
  sb::dds::DomainParticipant out({domain, partition + ".ping"});
  sb::dds::DomainParticipant in({domain, partition + ".pong"});
  sb::dds::DataWriter<stereoball_msg_StereoFrame> writer(out, sb::topics::kStereoFrame,
                                                         frame_qos());
  sb::dds::DataReader<stereoball_msg_StereoFrame> reader(in, sb::topics::kStereoFrame, frame_qos());
  sb::dds::WaitSet ws(in);
  sb::dds::ReadCondition cond(reader.handle());
  ws.attach(cond.handle(), 1);
  if (!writer.wait_for_readers(1, 10 * kSecond) || !reader.wait_for_writers(1, 10 * kSecond)) {
    throw std::runtime_error("pong process did not match within 10 s");
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  Frame frame;
  std::vector<Sample> samples;
  size_t lost = 0;
  const int64_t t0 = sb::node::monotonic_ns();
  // At least as many seconds as ddsperf pings, so both have as many per-second percentiles.
  const int64_t min_end = t0 + static_cast<int64_t>(min_seconds * kSecond);
  int sent_frames = 0;
  for (int i = 0; i < frames + 20 || sb::node::monotonic_ns() < min_end; ++i, ++sent_frames) {
    frame.msg.seq = static_cast<uint64_t>(i);
    const int64_t sent = sb::node::monotonic_ns();
    writer.write(frame.msg);
    bool got = false;
    // Best effort: a lost frame times out after 100 ms and is counted, not waited for.
    while (!got && sb::node::monotonic_ns() - sent < 100'000'000) {
      if (!wait_data(ws, 100'000'000)) continue;
      auto samples = reader.take_loaned();
      for (size_t k = 0; k < samples.size(); ++k) {
        if (samples.valid(k) && samples[k].seq == static_cast<uint64_t>(i)) got = true;
      }
    }
    const int64_t now = sb::node::monotonic_ns();
    if (!got)
      ++lost;
    else if (i >= 20)
      samples.push_back({sent, (now - sent) / 2e3});  // first 20 warm up
  }
  const double elapsed_s = (sb::node::monotonic_ns() - t0) * 1e-9;
  Figures f = per_second_figures(samples);
  f.rate_hz = f.count / elapsed_s;
  f.mbps = f.rate_hz * static_cast<double>(g_ddsperf_sample_bytes) / 1e6;
  if (lost)
    std::fprintf(stderr, "  (ours: %zu of %d frames lost and skipped)\n", lost, sent_frames);
  return f;
}

// Starts ARGS with its output in LOG_PATH, in ENV ("NAME=VALUE") if given, else in ours.
pid_t spawn(const std::vector<std::string>& args, const std::string& log_path,
            const std::vector<std::string>* env = nullptr) {
  // Everything the child needs is built before fork: this process has DDS threads.
  std::vector<std::string> arg_copy = args, env_copy = env ? *env : std::vector<std::string>{};
  std::vector<char*> argv, envp;
  for (auto& a : arg_copy) argv.push_back(a.data());
  argv.push_back(nullptr);
  for (auto& e : env_copy) envp.push_back(e.data());
  envp.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    if (env)
      execvpe(argv[0], argv.data(), envp.data());
    else
      execvp(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

int reap(pid_t pid, int timeout_s) {
  for (int i = 0; i < timeout_s * 100; ++i) {
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  return -1;
}

std::string self_path() {
  return std::filesystem::read_symlink("/proc/self/exe").string();
}

Figures ours(int domain, int frames, double min_seconds, int run) {
  const std::string partition = "bench." + std::to_string(getpid()) + "." + std::to_string(run);
  const pid_t pong =
      spawn({self_path(), "--pong", "--partition", partition, "--domain", std::to_string(domain),
             "--seconds", "120", g_reliable ? "--reliable" : "--best-effort"},
            "/tmp/sb-bench-pong.log");
  Figures f;
  try {
    f = run_ping(domain, partition, frames, min_seconds);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ours: %s\n", e.what());
  }
  kill(pong, SIGKILL);
  reap(pong, 5);
  return f;
}

// Parses ddsperf's per-second ping lines: "... size S mean ..us min ..us 50% Xus 90% ..us 99% Yus
// max ..us cnt N".
Figures ddsperf(int domain, int seconds, bool best_effort) {
  // Its own domain: ddsperf has no partitions.
  const bt::DdsperfSetup setup{domain + 1, best_effort, g_ddsperf_sample_bytes, seconds};
  const std::string tag = best_effort ? "best-effort" : "reliable";
  const pid_t pong = spawn(bt::ddsperf_pong_args(setup),
                           "/tmp/sb-bench-ddsperf-pong-" + tag + ".log", &g_ddsperf_env);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const pid_t ping = spawn(bt::ddsperf_ping_args(setup),
                           "/tmp/sb-bench-ddsperf-ping-" + tag + ".log", &g_ddsperf_env);
  reap(ping, seconds + 15);
  kill(pong, SIGKILL);
  reap(pong, 5);
  std::ifstream in("/tmp/sb-bench-ddsperf-ping-" + tag + ".log");
  std::stringstream log;
  log << in.rdbuf();
  // Seconds with a handful of round trips are left out of the percentiles, as ours are.
  const bt::DdsperfSeconds s = bt::parse_ddsperf_ping_log(log.str());
  if (s.sparse_seconds > 0) {
    std::fprintf(stderr, "  (ddsperf %s: %zu of %zu seconds with fewer than %zu round trips)\n",
                 tag.c_str(), s.sparse_seconds, s.seconds, bt::kMinSamplesPerSecond);
  }
  Figures f;
  f.median_us = median(s.medians_us);
  f.p99_us = median(s.p99s_us);
  f.second_medians_us = s.medians_us;
  f.second_p99s_us = s.p99s_us;
  f.count = s.count;
  f.rate_hz = s.seconds == 0 ? 0 : static_cast<double>(s.count) / static_cast<double>(s.seconds);
  f.mbps = f.rate_hz * static_cast<double>(g_ddsperf_sample_bytes) / 1e6;
  return f;
}

// Our frame's serialized size without the 4-byte encapsulation header, as it travels: one frame
// written to a serialized reader in this process. 0 when it could not be measured.
size_t measure_frame_sample_bytes(int domain) {
  try {
    sb::dds::DomainParticipant p({domain, "bench.size." + std::to_string(getpid())});
    sb::dds::SerializedReader reader(p, sb::topics::kStereoFrame.spec, frame_qos());
    sb::dds::DataWriter<stereoball_msg_StereoFrame> writer(p, sb::topics::kStereoFrame,
                                                           frame_qos());
    if (!writer.wait_for_readers(1, 5 * kSecond)) return 0;
    Frame frame;
    writer.write(frame.msg);
    std::vector<sb::dds::SerializedSample> got;
    const int64_t deadline = sb::node::monotonic_ns() + 5 * kSecond;
    while (got.empty() && sb::node::monotonic_ns() < deadline) {
      if (reader.take(got, 1) == 0) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return got.empty() || got.front().cdr.size() < 4 ? 0 : got.front().cdr.size() - 4;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "measuring our sample size: %s\n", e.what());
    return 0;
  }
}

// The Cyclone configuration our participants run under, for ddsperf's CYCLONEDDS_URI, and how
// to name it: keyless, the layer's loopback-only domain; with a key, the deployment's.
std::pair<std::string, std::string> our_cyclone_config() {
  sb::deployment::import_env_file();
  if (sb::dds::resolve_key_file(std::nullopt).empty())
    return {sb::dds::keyless_cyclone_config(),
            "loopback-only (the keyless built-in, as config/cyclonedds/loopback.xml)"};
  const auto& config = sb::deployment::use_deployment_dds_config();
  if (!config) return {"", "Cyclone's defaults (" + config.error() + ")"};
  return {config->uri, config->uri.empty() ? "Cyclone's defaults" : config->uri};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"stereoball bench transport: 640x480 stereo frame latency/throughput vs ddsperf"};
  bool pong = false;
  int domain = sb::dds::domain_from_env(77);
  std::string partition;
  double seconds = 60;
  int frames = 1000, runs = 3, slices = 3;
  bool with_ddsperf = true;
  app.add_flag("--pong", pong, "internal: run the echo side");
  app.add_option("--domain", domain, "DDS domain (ddsperf uses domain+1)")
      ->check(CLI::Range(0, 231));
  app.add_option("--partition", partition, "internal");
  app.add_option("--seconds", seconds, "internal");
  app.add_option("--frames", frames, "frames per run (>= 1000 for the report)")
      ->check(CLI::Range(10, 1000000));
  app.add_option("--runs", runs, "runs of each side; medians are reported")
      ->check(CLI::Range(1, 20));
  app.add_option("--slices", slices,
                 "each run alternates ours and ddsperf this many times (frames split between "
                 "the slices), so a change of load during a run hits both sides alike")
      ->check(CLI::Range(1, 10))
      ->capture_default_str();
  app.add_flag("!--no-ddsperf", with_ddsperf, "skip the ddsperf comparison");
  app.add_flag("--reliable,!--best-effort", g_reliable,
               "our frames reliable instead of the table's best-effort");
  CLI11_PARSE(app, argc, argv);
  if (pong) return run_pong(domain, partition, seconds);

  const auto [cyclone_uri, cyclone_name] = our_cyclone_config();
  std::vector<std::string> env;
  for (char** e = environ; *e; ++e) env.emplace_back(*e);
  g_ddsperf_env = bt::with_cyclone_uri(env, cyclone_uri);
  const size_t our_sample_bytes = measure_frame_sample_bytes(domain);
  const size_t pixel_bytes = 2ul * kWidth * kHeight * 3;
  // Unmeasured, ddsperf sends the pixels' size and the notes say the sizes differ.
  g_ddsperf_sample_bytes = our_sample_bytes > 0 ? our_sample_bytes : pixel_bytes;

  const bool have_ddsperf = std::system("command -v ddsperf >/dev/null 2>&1") == 0;
  if (with_ddsperf && !have_ddsperf) {
    std::fprintf(stderr, "ddsperf not found (package cyclonedds-tools); comparison skipped\n");
    with_ddsperf = false;
  }
  // Each slice: at least 3 s of ddsperf (its first second, discovery, is dropped).
  const int slice_frames = std::max(10, frames / slices);
  const int ddsperf_seconds = std::max(3, slice_frames / 500 + 2);
  std::vector<Figures> mine, theirs_rel, theirs_be;
  std::vector<double> p99_ratios, median_ratios;
  for (int run = 0; run < runs; ++run) {
    // Ours and ddsperf with our reliability in alternating slices (A B, B A, A B, ...), so both
    // see the same load on this shared machine; the other reliability afterwards, for reference.
    auto& same = g_reliable ? theirs_rel : theirs_be;
    auto& other = g_reliable ? theirs_be : theirs_rel;
    std::vector<Figures> mine_slices, same_slices;
    for (int slice = 0; slice < slices; ++slice) {
      const bool ddsperf_first = with_ddsperf && (run * slices + slice) % 2 == 1;
      if (ddsperf_first) same_slices.push_back(ddsperf(domain, ddsperf_seconds, !g_reliable));
      mine_slices.push_back(ours(domain, slice_frames, ddsperf_seconds - 1, run * slices + slice));
      if (with_ddsperf && !ddsperf_first)
        same_slices.push_back(ddsperf(domain, ddsperf_seconds, !g_reliable));
    }
    mine.push_back(pooled(mine_slices));
    if (with_ddsperf) same.push_back(pooled(same_slices));
    std::printf(
        "run %d: ours (%s keep-last-1) median %.0f us p99 %.0f us (p99 of all %zu samples %.0f "
        "us), %.1f frames/s\n",
        run + 1, g_reliable ? "reliable" : "best-effort", mine.back().median_us, mine.back().p99_us,
        mine.back().count, mine.back().overall_p99_us, mine.back().rate_hz);
    if (with_ddsperf) {
      other.push_back(ddsperf(domain, ddsperf_seconds, g_reliable));
      if (same.back().second_medians_us.empty() || mine.back().second_medians_us.empty()) {
        std::printf(
            "run %d: no ratio: %s measured no second with %zu round trips or more (pings "
            "lost; see /tmp/sb-bench-*.log)\n",
            run + 1, mine.back().second_medians_us.empty() ? "ours" : "ddsperf",
            bt::kMinSamplesPerSecond);
        continue;
      }
      median_ratios.push_back(mine.back().median_us / same.back().median_us);
      p99_ratios.push_back(mine.back().p99_us / same.back().p99_us);
      std::printf(
          "run %d: ddsperf best-effort median %.0f us p99 %.0f us; reliable median %.0f us p99 "
          "%.0f us; ratio ours/ddsperf (%s) median %.2f p99 %.2f\n",
          run + 1, theirs_be.back().median_us, theirs_be.back().p99_us, theirs_rel.back().median_us,
          theirs_rel.back().p99_us, g_reliable ? "reliable" : "best-effort", median_ratios.back(),
          p99_ratios.back());
    }
    std::fflush(stdout);
  }
  // Over the runs that measured something (a run with no full second has no figures).
  auto med = [](const std::vector<Figures>& v, double Figures::*field) {
    std::vector<double> x;
    for (const auto& f : v) {
      if (!f.second_medians_us.empty()) x.push_back(f.*field);
    }
    return median(x);
  };
  std::printf(
      "\n640x480x3 stereo frame (%zu B of pixels, %zu B serialized), one-way latency = round "
      "trip / 2, %d frames x %d runs\n",
      pixel_bytes, our_sample_bytes, frames, runs);
  std::printf("%-34s %12s %12s %14s %10s\n", "", "median (us)", "p99 (us)", "pingpong (Hz)",
              "MB/s");
  std::printf("%-34s %12.0f %12.0f %14.1f %10.1f\n", "stereoball (dds layer, typed)",
              med(mine, &Figures::median_us), med(mine, &Figures::p99_us),
              med(mine, &Figures::rate_hz), med(mine, &Figures::mbps));
  if (with_ddsperf) {
    // The row of our reliability ran interleaved with ours; the other after each run.
    const char* be_label = g_reliable ? "ddsperf best-effort (reference)" : "ddsperf best-effort";
    const char* rel_label = g_reliable ? "ddsperf reliable" : "ddsperf reliable (reference)";
    std::printf("%-34s %12.0f %12.0f %14.1f %10.1f\n", be_label,
                med(theirs_be, &Figures::median_us), med(theirs_be, &Figures::p99_us),
                med(theirs_be, &Figures::rate_hz), med(theirs_be, &Figures::mbps));
    std::printf("%-34s %12.0f %12.0f %14.1f %10.1f\n", rel_label,
                med(theirs_rel, &Figures::median_us), med(theirs_rel, &Figures::p99_us),
                med(theirs_rel, &Figures::rate_hz), med(theirs_rel, &Figures::mbps));
    bt::ComparisonFacts facts;
    facts.our_sample_bytes = our_sample_bytes;
    facts.ddsperf_sample_bytes = g_ddsperf_sample_bytes;
    facts.our_pixel_bytes = pixel_bytes;
    facts.reliable = g_reliable;
    facts.config = cyclone_name;
    for (const auto& note : bt::comparison_notes(facts)) std::printf("%s\n", note.c_str());
    std::printf(
        "(reference) rows: the other reliability, run after each run's interleaved slices, "
        "not part of the ratio\n");
    if (p99_ratios.empty()) {
      std::printf("ratio ours/ddsperf: no run measured both sides\n");
      return 0;
    }
    const auto [p99_min, p99_max] = std::minmax_element(p99_ratios.begin(), p99_ratios.end());
    const auto [med_min, med_max] = std::minmax_element(median_ratios.begin(), median_ratios.end());
    std::printf(
        "ratio ours/ddsperf per run (same reliability, %s, measured the same way: median over "
        "the seconds of each second's percentile): median %.2f (%.2f..%.2f), p99 %.2f "
        "(%.2f..%.2f) over %zu runs; p99 <= 1.2 in %ld of them\n",
        g_reliable ? "reliable" : "best-effort", median(median_ratios), *med_min, *med_max,
        median(p99_ratios), *p99_min, *p99_max, p99_ratios.size(),
        std::count_if(p99_ratios.begin(), p99_ratios.end(), [](double r) { return r <= 1.2; }));
  }
  return 0;
}
