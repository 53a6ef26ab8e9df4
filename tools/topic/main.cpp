// stereoball topic list | echo TOPIC | hz TOPIC — inspect the running system over the topic table.

#include "common/util/cli11.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <deque>
#include <numeric>
#include <string>

#include "common/dds/reader.hpp"
#include "common/dds/serialized.hpp"
#include "common/dds/waitset.hpp"
#include "common/node/common_flags.hpp"
#include "common/node/node_runner.hpp"
#include "print.hpp"

namespace sb = stereoball;

namespace {

std::atomic<bool> g_interrupted{false};
void on_signal(int) {
  g_interrupted = true;
}

const char* reliability(const sb::topics::QosSpec& q) {
  return q.reliability == sb::topics::Reliability::kReliable ? "reliable" : "best-effort";
}

int list_topics() {
  std::printf("%-20s %-34s %-12s %-16s %-6s %s\n", "TOPIC", "TYPE", "RELIABILITY", "DURABILITY",
              "DEPTH", "DESCRIPTION");
  for (const auto& t : sb::topics::all()) {
    std::printf("%-20.*s %-34.*s %-12s %-16s %-6d %.*s\n", static_cast<int>(t.name.size()),
                t.name.data(), static_cast<int>(t.type_name.size()), t.type_name.data(),
                reliability(t.qos),
                t.qos.durability == sb::topics::Durability::kTransientLocal ? "transient-local"
                                                                            : "volatile",
                t.qos.history_depth, static_cast<int>(t.description.size()), t.description.data());
  }
  return 0;
}

// Deadline helper: 0 seconds means "no deadline".
struct Deadline {
  explicit Deadline(double seconds)
      : end(seconds > 0 ? sb::node::monotonic_ns() + static_cast<int64_t>(seconds * 1e9)
                        : INT64_MAX) {}
  bool passed() const { return sb::node::monotonic_ns() >= end; }
  int64_t end;
};

template <typename T>
int echo_typed(sb::dds::DomainParticipant& participant, const sb::topics::Topic<T>& topic,
               int count, double timeout_s) {
  sb::dds::DataReader<T> reader(participant, topic);
  sb::dds::WaitSet waitset(participant);
  sb::dds::ReadCondition condition(reader.handle());
  waitset.attach(condition.handle(), 1);
  const Deadline deadline(timeout_s);
  int printed = 0;
  while (!g_interrupted && !deadline.passed() && (count == 0 || printed < count)) {
    waitset.wait(100'000'000);
    for (auto& sample : reader.take()) {
      std::printf("%s---\n", sb::tools::to_text(*sample).c_str());
      std::fflush(stdout);
      if (count && ++printed >= count) break;
    }
  }
  if (printed == 0 && !g_interrupted) {
    std::fprintf(stderr, "stereoball topic echo: no sample on '%.*s' within %.1f s\n",
                 static_cast<int>(topic.spec.name.size()), topic.spec.name.data(), timeout_s);
    return 1;
  }
  return 0;
}

int echo_topic(const sb::node::CommonOptions& options, const std::string& name, int count,
               double timeout_s) {
  if (!sb::topics::find(name)) {
    std::fprintf(stderr,
                 "stereoball topic echo: unknown topic '%s' (see `stereoball topic list`)\n",
                 name.c_str());
    return 2;
  }
  sb::dds::DomainParticipant participant({options.domain_id, options.partition, options.key_file});
  int rc = 2;
  sb::topics::for_each([&](const auto& topic) {
    if (topic.spec.name == name) rc = echo_typed(participant, topic, count, timeout_s);
  });
  return rc;
}

struct HzStats {
  double rate_hz, min_s, max_s, std_s, bytes_per_s, mean_bytes;
  size_t window;
};

HzStats compute(const std::deque<std::pair<int64_t, size_t>>& window) {
  HzStats s{};
  s.window = window.size();
  if (window.size() < 2) return s;
  std::vector<double> dt;
  for (size_t i = 1; i < window.size(); ++i)
    dt.push_back((window[i].first - window[i - 1].first) * 1e-9);
  const double mean = std::accumulate(dt.begin(), dt.end(), 0.0) / dt.size();
  double var = 0;
  for (double d : dt) var += (d - mean) * (d - mean);
  s.rate_hz = mean > 0 ? 1.0 / mean : 0;
  s.min_s = *std::min_element(dt.begin(), dt.end());
  s.max_s = *std::max_element(dt.begin(), dt.end());
  s.std_s = std::sqrt(var / dt.size());
  size_t bytes = 0;
  for (const auto& w : window) bytes += w.second;
  s.mean_bytes = static_cast<double>(bytes) / window.size();
  s.bytes_per_s = s.mean_bytes * s.rate_hz;
  return s;
}

std::string human_bytes(double bytes) {
  char buf[32];
  if (bytes >= 1e6)
    std::snprintf(buf, sizeof buf, "%.2f MB", bytes / 1e6);
  else if (bytes >= 1e3)
    std::snprintf(buf, sizeof buf, "%.2f KB", bytes / 1e3);
  else
    std::snprintf(buf, sizeof buf, "%.0f B", bytes);
  return buf;
}

int hz_topic(const sb::node::CommonOptions& options, const std::string& name, size_t window_size,
             double duration_s) {
  const sb::topics::TopicSpec* spec = sb::topics::find(name);
  if (!spec) {
    std::fprintf(stderr, "stereoball topic hz: unknown topic '%s' (see `stereoball topic list`)\n",
                 name.c_str());
    return 2;
  }
  sb::dds::DomainParticipant participant({options.domain_id, options.partition, options.key_file});
  // A deeper history than the table's so bursts are measured, not collapsed.
  sb::topics::QosSpec qos = spec->qos;
  qos.history_depth = 64;
  sb::dds::SerializedReader reader(participant, *spec, qos);
  sb::dds::WaitSet waitset(participant);
  sb::dds::ReadCondition condition(reader.handle());
  waitset.attach(condition.handle(), 1);
  std::deque<std::pair<int64_t, size_t>> window;
  std::vector<sb::dds::SerializedSample> samples;
  const Deadline deadline(duration_s);
  int64_t next_print = sb::node::monotonic_ns() + 1'000'000'000;
  uint64_t total = 0;
  while (!g_interrupted && !deadline.passed()) {
    waitset.wait(50'000'000);
    samples.clear();
    reader.take(samples, 256);
    const int64_t now = sb::node::monotonic_ns();
    for (const auto& s : samples) {
      window.emplace_back(now, s.cdr.size());
      ++total;
      if (window.size() > window_size) window.pop_front();
    }
    if (now >= next_print) {
      next_print += 1'000'000'000;
      if (window.size() < 2) {
        std::printf("no new messages\n");
      } else {
        const HzStats s = compute(window);
        std::printf(
            "average rate: %.3f Hz\n\tmin: %.4fs max: %.4fs std dev: %.5fs window: %zu\n"
            "\tbandwidth: %s/s (mean size %s)\n",
            s.rate_hz, s.min_s, s.max_s, s.std_s, s.window, human_bytes(s.bytes_per_s).c_str(),
            human_bytes(s.mean_bytes).c_str());
      }
      std::fflush(stdout);
    }
  }
  return total > 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  CLI::App app{"stereoball topic: list the topic table, print samples, measure rates"};
  app.require_subcommand(1);
  app.fallthrough();  // shared flags may follow the subcommand
  sb::node::CommonOptions options;
  sb::node::add_common_flags(app, options, "", false);
  auto* list = app.add_subcommand("list", "every topic with its type and QoS");
  std::string name;
  int count = 0;
  double timeout_s = 0;
  auto* echo = app.add_subcommand("echo", "print samples of a topic (images summarised)");
  echo->add_option("topic", name, "topic name, e.g. ball/track")->required();
  echo->add_option("-n,--count", count, "stop after N samples (0 = until Ctrl-C)")
      ->check(CLI::NonNegativeNumber);
  echo->add_option("--timeout", timeout_s, "give up after S seconds (0 = never)")
      ->check(CLI::NonNegativeNumber);
  size_t window = 100;
  double duration_s = 0;
  auto* hz =
      app.add_subcommand("hz", "rate, jitter and bandwidth of a topic, printed every second");
  hz->add_option("topic", name, "topic name, e.g. stereo/frame")->required();
  hz->add_option("-w,--window", window, "samples in the rolling window")
      ->check(CLI::Range(2, 100000));
  hz->add_option("--duration", duration_s, "stop after S seconds (0 = until Ctrl-C)")
      ->check(CLI::NonNegativeNumber);
  CLI11_PARSE(app, argc, argv);
  try {
    if (list->parsed()) return list_topics();
    if (echo->parsed()) return echo_topic(options, name, count, timeout_s);
    if (hz->parsed()) return hz_topic(options, name, window, duration_s);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "stereoball topic: %s\n", e.what());
    return 1;
  }
  return 2;
}
