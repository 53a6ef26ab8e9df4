#pragma once
// A chaos run and its options (chaos_run.cpp: the nodes, the faults; chaos_judge.cpp: the
// checks on its files and the report).

#include <sys/types.h>

#include <cstddef>
#include <cstdint>
#include <map>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "chaos_checks.hpp"
#include "chaos_plan.hpp"
#include "chaos_processes.hpp"

namespace stereoball::bench_chaos {

/// Where a program runs: this host, or the robot's or the workstation's namespace.
enum class Host { kLocal, kRobot, kWorkstation };

/// A process of the system the run keeps alive (restarted when it exits unasked).
struct Node {
  std::string name;
  std::vector<std::string> argv;
  Host host = Host::kLocal;
  pid_t pid = -1;
  int64_t started_ns = 0;
  bool expect_exit = false;
  int restarts = 0;
};

/// Memory samples per process instance.
struct MemoryTrack {
  std::map<pid_t, MemorySpan> spans;  // per process instance
};

/// What main.cpp's flags set: the run's length, seed, files and memory rule, and a child mode.
struct Options {
  double minutes = 1.0;
  uint64_t seed = 1;
  std::string json_path;
  std::string out_dir;
  std::string bin_dir;
  std::string scenario = "ball_kicked_past_right";
  double mean_gap_s = 8.0;
  double warmup_s = 10.0;
  bool one_round = false;  // each fault kind once, then stop kTail after the last
  bool no_netns = false;
  double memory_min_span_s = 300.0;
  double memory_settle_s = 120.0;
  double memory_max_growth_percent = 5.0;
  int domain = 0;
  std::string partition;
  // Child modes (the run starts itself for these).
  std::string child;
  double child_seconds = 0;
};

/// One chaos run: the nodes started, the faults done on schedule, then judged from its files.
class Run {
 public:
  explicit Run(Options o) : o_(std::move(o)) {}
  int main();  ///< the whole run; exit code (0 all checks passed, 1 one failed, 2 setup)

 private:
  // argv run on host (in its namespace, with its DDS configuration and key file); dds: the
  // program takes --domain/--partition.
  std::vector<std::string> wrap(Host host, const std::vector<std::string>& argv,
                                const std::string& key_file, bool dds = true) const;
  void start(Node& n);
  void poll();  // reap exits (restart the unexpected ones), sample memory
  void wait_until(int64_t t_ns);
  // Runs a program to completion (name in the bin dir, or a path), counting failures.
  int tool(const std::string& name, Host host, std::vector<std::string> args,
           const std::string& key_file, int64_t timeout_ns);
  // This program in a child mode (flood or rogue) for seconds, in the robot namespace.
  void tool_child(const std::string& mode, double seconds);
  void stop_all();
  // main's steps: the out dir's keys and files (0, else the exit code), the namespaces (their
  // note for the report), the nodes (0, else the exit code), the faults (how many planned),
  // then the checks on the files and the report (exit code).
  int prepare_files();
  std::string make_namespaces();
  int start_nodes();
  size_t run_faults();
  int judge(const std::string& netns_note, size_t planned);
  // The summary on stdout, and --json's file (false when it cannot be written); exit code.
  int report(const std::vector<CheckResult>& checks, const std::vector<TopicLoss>& losses,
             const std::map<std::string, uint64_t>& recorded, const std::string& netns_note,
             size_t planned);
  void print_summary(bool passed, const std::vector<CheckResult>& checks,
                     const std::vector<TopicLoss>& losses,
                     const std::map<std::string, uint64_t>& recorded, const std::string& netns_note,
                     size_t planned) const;
  bool write_json(bool passed, const std::vector<CheckResult>& checks,
                  const std::vector<TopicLoss>& losses,
                  const std::map<std::string, uint64_t>& recorded,
                  const std::string& netns_note) const;
  // write_json's memory, topics and recorded samples (the end of the object).
  void json_samples(std::ostream& j, const std::vector<TopicLoss>& losses,
                    const std::map<std::string, uint64_t>& recorded) const;
  void do_fault(const Fault& f);
  // do_fault's two longest faults (seconds: f's duration as the note says it).
  void kill_and_restart(const Fault& f, const std::string& seconds);
  void hold_estop(const Fault& f, const std::string& seconds);
  MemoryRule memory_rule() const {
    MemoryRule r;
    r.settle_ns = static_cast<int64_t>(o_.memory_settle_s * 1e9);
    r.min_span_ns = static_cast<int64_t>(o_.memory_min_span_s * 1e9);
    r.max_growth_percent = o_.memory_max_growth_percent;
    return r;
  }
  std::string bin(const std::string& name) const { return o_.bin_dir + "/" + name; }
  std::string log_file(const std::string& name) const { return o_.out_dir + "/" + name + ".log"; }
  void note(const std::string& text);

  Options o_;
  Namespaces ns_;
  bool netns_ = false;
  std::string key_file_, rogue_key_, base_log_, mcap_;
  std::vector<Node> nodes_;  // 0..3 may be killed; the recorder is last
  std::vector<std::string> unexpected_;
  MemoryTrack memory_;
  int64_t next_memory_ns_ = 0;
  Timeline timeline_;
  std::map<std::string, int> fault_counts_;
  int tool_failures_ = 0;
  int child_runs_ = 0;
  std::string self_;
  int64_t start_ns_ = now_ns();
};

}  // namespace stereoball::bench_chaos
