// The outputs a bench run leaves in the output folder, and what they say about that run: ran to
// its end, still running, stopped part way, or failed.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "bench_table.hpp"
#include "report.hpp"

namespace stereoball::bench_report {

// NAME.running: written when a bench starts, removed once its NAME.cmd records how it ended.
struct RunningMarker {
  long pid = 0;          // the bench's process id
  std::string program;   // its executable's file name (tells a reused pid apart)
  std::string date_utc;  // when it started
};

// The marker's text (three lines: pid, program, date).
std::string running_marker_text(const RunningMarker& marker);

// The marker in TEXT, or nullopt when it is not one.
std::optional<RunningMarker> parse_running_marker(const std::string& text);

// True while process PID runs program PROGRAM.
using ProcessRuns = std::function<bool(long pid, const std::string& program)>;

// /proc/PID/cmdline's first word ends in PROGRAM.
bool process_runs(long pid, const std::string& program);

// The saved outputs of ENTRY in DIR (NAME.txt, NAME.cmd, NAME.json, NAME.running). Figures only
// come from a run whose NAME.cmd records its end: a NAME.running left behind is "running" while
// its process runs and "incomplete" after; output without NAME.cmd, or a run stopped at the time
// limit or by a signal, is "incomplete".
BenchOutcome read_saved(const BenchEntry& entry, const std::filesystem::path& dir,
                        const ProcessRuns& runs = process_runs);

}  // namespace stereoball::bench_report
