// After a chaos run: the base log and the recording read back, the checks (chaos_checks) run on
// them, the memory samples and the timeline, and the summary printed and written as JSON.
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "chaos_children.hpp"
#include "chaos_run.hpp"
#include "common/util/json_text.hpp"
#include "recorder/core/reader.hpp"
#include "recorder/io/file_io.hpp"

namespace sb = stereoball;
namespace bc = stereoball::bench_chaos;

namespace stereoball::bench_chaos {
namespace {

// The simulator's base log: its events, how many lines did not parse and the first one's error.
struct BaseLog {
  std::vector<sb::base::BaseEvent> events;
  uint64_t bad_lines = 0;
  std::string first_bad;
};

BaseLog read_base_log(const std::string& path) {
  BaseLog log;
  auto& [events, bad_lines, first_bad] = log;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    auto e = sb::base::parse_base_event(line);
    if (e) {
      events.push_back(*e);
    } else if (bad_lines++ == 0) {
      first_bad = e.error();
    }
  }
  return log;
}

// What `stereoball record` wrote: the sequence numbers of ground truth and commands, the
// samples per topic, how many could not be decoded, and why the file could not be read.
struct Recording {
  std::map<std::string, std::vector<bc::SeqSample>> seqs;
  std::map<std::string, uint64_t> recorded;
  uint64_t undecodable = 0;
  std::string mcap_error;
};

Recording read_recording(const std::string& path) {
  Recording rec;
  auto& [seqs, recorded, undecodable, mcap_error] = rec;
  if (auto source = sb::recorder::FileSource::open(path); !source) {
    mcap_error = source.error();
  } else {
    sb::recorder::McapReader reader(**source);
    if (auto st = reader.open(); !st) {
      mcap_error = st.error();
    } else {
      const auto& channels = reader.summary().channels;
      auto st2 = reader.for_each_message([&](const sb::recorder::MessageView& m) {
        const auto ch = channels.find(m.channel_id);
        if (ch == channels.end()) return true;
        const std::string& topic = ch->second.topic;
        if (topic != "sim/ground_truth" && topic != "cmd/velocity") {
          ++recorded[topic];
          return true;
        }
        const auto seq = bc::cdr_leading_u64(m.data);
        if (!seq) {
          ++undecodable;
          return true;
        }
        if (topic == "cmd/velocity" && *seq >= kRogueSeqBase) {
          ++recorded["cmd/velocity (rogue)"];
          return true;
        }
        ++recorded[topic];
        seqs[topic].push_back({*seq, static_cast<int64_t>(m.log_time_ns)});
        return true;
      });
      if (!st2) mcap_error = st2.error();
    }
  }
  return rec;
}

}  // namespace

int Run::judge(const std::string& netns_note, size_t planned) {
  auto [events, bad_lines, first_bad] = read_base_log(base_log_);
  auto [seqs, recorded, undecodable, mcap_error] = read_recording(mcap_);
  bc::CheckParams params;
  std::vector<bc::Interval> link_excused;
  for (const auto& cut : timeline_.link_cuts)
    link_excused.push_back({cut.begin_ns, cut.end_ns + params.link_settle_ns});
  std::vector<bc::TopicLoss> losses;
  // Ground truth is published beside the recorder; commands come over the link.
  losses.push_back(bc::count_losses("sim/ground_truth", seqs["sim/ground_truth"], {}));
  losses.push_back(bc::count_losses("cmd/velocity", seqs["cmd/velocity"], link_excused));

  std::vector<bc::CheckResult> checks;
  checks.push_back(bc::check_no_unsafe_motion(events, params));
  checks.push_back(bc::check_estop_held(events, timeline_, params));
  bc::CheckResult lost = bc::check_none_lost(losses);
  if (!mcap_error.empty() || undecodable > 0) {
    lost.passed = false;
    lost.detail += "; recording: " + (mcap_error.empty() ? "" : mcap_error + ", ") +
                   std::to_string(undecodable) + " undecodable samples";
  }
  checks.push_back(lost);
  std::vector<bc::MemorySpan> spans;
  for (const auto& [pid, m] : memory_.spans) spans.push_back(m);
  checks.push_back(bc::check_memory(spans, memory_rule()));
  checks.push_back(bc::check_no_crashes(unexpected_));
  bc::CheckResult log_check;
  log_check.name = "base_log_readable";
  log_check.passed = !events.empty() && bad_lines <= 1;  // a SIGKILL may cut the last line
  log_check.detail = std::to_string(events.size()) + " events, " + std::to_string(bad_lines) +
                     " unreadable line(s)" + (first_bad.empty() ? "" : " (" + first_bad + ")");
  checks.push_back(log_check);
  return report(checks, losses, recorded, netns_note, planned);
}

using sb::util::json_escape;

int Run::report(const std::vector<bc::CheckResult>& checks,
                const std::vector<bc::TopicLoss>& losses,
                const std::map<std::string, uint64_t>& recorded, const std::string& netns_note,
                size_t planned) {
  bool passed = true;
  for (const auto& c : checks) passed = passed && c.passed;
  print_summary(passed, checks, losses, recorded, netns_note, planned);
  if (!o_.json_path.empty() && !write_json(passed, checks, losses, recorded, netns_note)) return 2;
  return passed ? 0 : 1;
}

void Run::print_summary(bool passed, const std::vector<bc::CheckResult>& checks,
                        const std::vector<bc::TopicLoss>& losses,
                        const std::map<std::string, uint64_t>& recorded,
                        const std::string& netns_note, size_t planned) const {
  std::printf("\n== stereoball bench chaos: %s ==\n", passed ? "PASS" : "FAIL");
  std::printf("seed %llu, %.1f min, %s\n", static_cast<unsigned long long>(o_.seed), o_.minutes,
              netns_note.c_str());
  std::printf("faults (%zu):", planned);
  for (const auto& [kind, n] : fault_counts_) std::printf(" %s %d", kind.c_str(), n);
  std::printf("; tool failures %d\n", tool_failures_);
  for (const auto& n : nodes_) std::printf("  %-18s restarts %d\n", n.name.c_str(), n.restarts);
  std::printf("\nchecks:\n");
  for (const auto& c : checks) {
    std::printf("  %-4s %-45s %s\n", c.passed ? (c.applicable ? "ok" : "n/a") : "FAIL",
                c.name.c_str(), c.detail.c_str());
  }
  const bc::MemoryRule rule = memory_rule();
  std::printf(
      "\nmemory (VmRSS; start->end: first sample %.0f s after each start to the last, not judged;"
      "\nsettled: lowest sample of the %.0f s from %.0f s after the start -> lowest of the last "
      "%.0f s, judged):\n",
      o_.warmup_s, rule.window_ns * 1e-9, rule.settle_ns * 1e-9, rule.window_ns * 1e-9);
  for (const auto& [pid, m] : memory_.spans) {
    std::printf("  %-18s pid %-7d start->end %8ld -> %8ld kB %+6.1f %% over %5.0f s",
                m.process.c_str(), pid, m.first_kb, m.last_kb, m.growth_percent(),
                (m.last_ns - m.first_ns) * 1e-9);
    const bc::SettledGrowth g = bc::settled_growth(m, rule);
    if (g.available) {
      std::printf("  settled %8ld -> %8ld kB %+6.1f %% over %5.0f s\n", g.from_kb, g.to_kb,
                  g.percent(), (g.to_ns - g.from_ns) * 1e-9);
    } else {
      std::printf("  settled -\n");
    }
  }
  std::printf("\npublished vs recorded (stereoball record, seq numbers of each publisher run):\n");
  for (const auto& t : losses) {
    std::printf("  %-18s published %8llu recorded %8llu lost %llu (link down %llu) runs %llu\n",
                t.topic.c_str(), static_cast<unsigned long long>(t.published),
                static_cast<unsigned long long>(t.recorded),
                static_cast<unsigned long long>(t.lost),
                static_cast<unsigned long long>(t.lost_link_down),
                static_cast<unsigned long long>(t.publisher_runs));
  }
  std::printf("  recorded in all:");
  for (const auto& [topic, n] : recorded)
    std::printf(" %s %llu", topic.c_str(), static_cast<unsigned long long>(n));
  std::printf("\nfiles: %s\n", o_.out_dir.c_str());
}

void Run::json_samples(std::ostream& j, const std::vector<bc::TopicLoss>& losses,
                       const std::map<std::string, uint64_t>& recorded) const {
  const bc::MemoryRule rule = memory_rule();
  j << "\n  ],\n  \"memory\": [";
  bool first = true;
  for (const auto& [pid, m] : memory_.spans) {
    j << (first ? "\n" : ",\n") << "    {\"process\": \"" << m.process << "\", \"pid\": " << pid
      << ", \"first_kb\": " << m.first_kb << ", \"last_kb\": " << m.last_kb
      << ", \"span_s\": " << (m.last_ns - m.first_ns) * 1e-9
      << ", \"growth_percent\": " << m.growth_percent();
    const bc::SettledGrowth g = bc::settled_growth(m, rule);
    if (g.available) {
      j << ", \"settled_from_kb\": " << g.from_kb << ", \"settled_to_kb\": " << g.to_kb
        << ", \"settled_span_s\": " << (g.to_ns - g.from_ns) * 1e-9
        << ", \"settled_growth_percent\": " << g.percent();
    }
    j << "}";
    first = false;
  }
  j << "\n  ],\n  \"topics\": [";
  first = true;
  for (const auto& t : losses) {
    j << (first ? "\n" : ",\n") << "    {\"topic\": \"" << t.topic
      << "\", \"published\": " << t.published << ", \"recorded\": " << t.recorded
      << ", \"lost\": " << t.lost << ", \"lost_link_down\": " << t.lost_link_down
      << ", \"duplicates\": " << t.duplicates << ", \"publisher_runs\": " << t.publisher_runs
      << "}";
    first = false;
  }
  j << "\n  ],\n  \"recorded\": {";
  first = true;
  for (const auto& [topic, n] : recorded) {
    j << (first ? "" : ", ") << "\"" << topic << "\": " << n;
    first = false;
  }
  j << "}\n}\n";
}

bool Run::write_json(bool passed, const std::vector<bc::CheckResult>& checks,
                     const std::vector<bc::TopicLoss>& losses,
                     const std::map<std::string, uint64_t>& recorded,
                     const std::string& netns_note) const {
  std::string command = "stereoball bench chaos --minutes " + std::to_string(o_.minutes) +
                        " --seed " + std::to_string(o_.seed) + (o_.one_round ? " --one-round" : "");
  std::ostringstream j;
  j << "{\n  \"command\": \"" << json_escape(command) << "\",\n  \"seed\": " << o_.seed
    << ",\n  \"minutes\": " << o_.minutes
    << ",\n  \"one_round\": " << (o_.one_round ? "true" : "false")
    << ",\n  \"namespaces\": " << (netns_ ? "true" : "false") << ",\n  \"namespaces_note\": \""
    << json_escape(netns_note) << "\",\n  \"passed\": " << (passed ? "true" : "false")
    << ",\n  \"tool_failures\": " << tool_failures_ << ",\n  \"faults\": {";
  bool first = true;
  for (const auto& [kind, n] : fault_counts_) {
    j << (first ? "" : ", ") << "\"" << kind << "\": " << n;
    first = false;
  }
  j << "},\n  \"restarts\": {";
  first = true;
  for (const auto& n : nodes_) {
    j << (first ? "" : ", ") << "\"" << n.name << "\": " << n.restarts;
    first = false;
  }
  j << "},\n  \"checks\": [";
  first = true;
  for (const auto& c : checks) {
    j << (first ? "\n" : ",\n") << "    {\"name\": \"" << c.name
      << "\", \"passed\": " << (c.passed ? "true" : "false")
      << ", \"applicable\": " << (c.applicable ? "true" : "false")
      << ", \"violations\": " << c.violations << ", \"detail\": \"" << json_escape(c.detail)
      << "\"}";
    first = false;
  }
  json_samples(j, losses, recorded);
  std::ofstream out(o_.json_path);
  out << j.str();
  if (!out) {
    std::fprintf(stderr, "stereoball bench chaos: cannot write %s\n", o_.json_path.c_str());
    return false;
  }
  return true;
}

}  // namespace stereoball::bench_chaos
