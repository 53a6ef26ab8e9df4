// docs/benchmarks.md from the benchmarks' own output: pure rendering, no I/O.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "bench_table.hpp"

namespace stereoball::bench_report {

// Where and when the figures were taken.
struct MachineInfo {
  std::string cpu_model;       // /proc/cpuinfo "model name"
  int cores = 0;               // logical cores
  std::string load;            // /proc/loadavg's first three fields at the start
  std::string date_utc;        // YYYY-MM-DD HH:MM UTC of the report
  std::string commit;          // git commit of the sources (with "-dirty" when modified)
  std::string report_command;  // the command that wrote the report
};

// "CPU model, N logical cores": how a bench's saved record and the report name a machine.
std::string machine_text(const MachineInfo& machine);

// What happened to one bench.
struct BenchOutcome {
  const BenchEntry* entry = nullptr;
  // kRan: ended and recorded its end; kRunning: its process still runs; kIncomplete: stopped
  // part way (time limit, signal, or no record of its end); kFailed: ended with an error.
  enum class State { kRan, kRunning, kIncomplete, kFailed, kNotRun } state = State::kNotRun;
  std::string command;          // the exact command that produced `output` (empty: not run)
  std::string date_utc;         // when it ran
  std::string load;             // load average (1, 5, 15 min) when it started, if recorded
  std::string commit;           // commit it ran at, if recorded and not the report's
  std::string machine;          // machine_text of where it ran, if recorded
  double seconds = 0.0;         // wall time of the run (0 when unknown)
  std::string output;           // the bench's standard output, as printed (or its JSON); empty
                                // while running or when incomplete (partial figures are none)
  bool output_is_json = false;  // only the bench's --json file was saved
  std::string reason;           // why it failed, is incomplete, runs still, or was not run
  std::optional<std::string> json_file;  // name of its JSON file beside the outputs, if any
};

// "ran", "running", "incomplete", "failed" or "not run".
std::string_view state_name(BenchOutcome::State state);

// The whole Markdown document: header (machine, date, commit, how to regenerate), then one
// section per outcome with its exact command and the bench's output verbatim.
std::string render_report(const MachineInfo& machine, const std::vector<BenchOutcome>& outcomes);

}  // namespace stereoball::bench_report
