#include "saved_outputs.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace stereoball::bench_report {
namespace fs = std::filesystem;

namespace {

std::string file_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// How a recorded end status reads: a run cut short by the time limit or a signal left partial
// output; any other status than "ok" is a failure of the bench itself.
BenchOutcome::State state_of_status(const std::string& status) {
  if (status == "ok") return BenchOutcome::State::kRan;
  if (status.rfind("stopped after", 0) == 0 || status.rfind("killed by signal", 0) == 0)
    return BenchOutcome::State::kIncomplete;
  return BenchOutcome::State::kFailed;
}

}  // namespace

std::string running_marker_text(const RunningMarker& marker) {
  return std::to_string(marker.pid) + "\n" + marker.program + "\n" + marker.date_utc + "\n";
}

std::optional<RunningMarker> parse_running_marker(const std::string& text) {
  std::istringstream in(text);
  std::string pid_line;
  RunningMarker m;
  if (!std::getline(in, pid_line) || !std::getline(in, m.program)) return std::nullopt;
  std::getline(in, m.date_utc);
  char* end = nullptr;
  m.pid = std::strtol(pid_line.c_str(), &end, 10);
  if (pid_line.empty() || *end != '\0' || m.pid <= 0 || m.program.empty()) return std::nullopt;
  return m;
}

bool process_runs(long pid, const std::string& program) {
  const std::string cmdline = file_text("/proc/" + std::to_string(pid) + "/cmdline");
  const std::string first = cmdline.substr(0, cmdline.find('\0'));
  return !first.empty() && fs::path(first).filename() == program;
}

BenchOutcome read_saved(const BenchEntry& entry, const fs::path& dir, const ProcessRuns& runs) {
  BenchOutcome o;
  o.entry = &entry;
  const fs::path txt = dir / (entry.name + ".txt");
  const fs::path json = dir / (entry.name + ".json");
  const fs::path cmd = dir / (entry.name + ".cmd");
  const fs::path marker_path = dir / (entry.name + ".running");
  o.command = user_command(entry);

  if (fs::exists(marker_path)) {
    const auto marker = parse_running_marker(file_text(marker_path));
    if (marker && runs(marker->pid, marker->program)) {
      o.state = BenchOutcome::State::kRunning;
      o.date_utc = marker->date_utc;
      o.reason = "started " + marker->date_utc + ", process " + std::to_string(marker->pid) +
                 "; its output so far is not a result";
    } else {
      o.state = BenchOutcome::State::kIncomplete;
      o.reason = "its run" +
                 (marker ? " (process " + std::to_string(marker->pid) + ", started " +
                               marker->date_utc + ")"
                         : std::string()) +
                 " ended without recording its end in " + entry.name +
                 ".cmd: stopped or killed part way, its output is partial";
    }
    return o;
  }

  if (fs::exists(txt)) {
    o.output = file_text(txt);
  } else if (entry.writes_json && fs::exists(json)) {
    o.output = file_text(json);
    o.output_is_json = true;
  } else {
    o.command.clear();
    o.reason = "no output saved";
    return o;
  }
  if (o.output_is_json) o.command += " --json " + entry.name + ".json";

  std::ifstream meta(cmd);
  std::string command, status, seconds;
  if (!(std::getline(meta, command) && std::getline(meta, o.date_utc) &&
        std::getline(meta, status) && std::getline(meta, seconds))) {
    o.state = BenchOutcome::State::kIncomplete;
    o.reason = fs::exists(cmd) ? entry.name + ".cmd is cut short: the run's end is not recorded"
                               : "no " + entry.name +
                                     ".cmd records how the run ended (stopped part way, or "
                                     "still running under another report)";
    o.output.clear();
    return o;
  }
  o.command = command;
  o.state = state_of_status(status);
  if (o.state != BenchOutcome::State::kRan) o.reason = status;
  o.seconds = std::atof(seconds.c_str());
  std::getline(meta, o.load);  // absent in outputs saved before these were recorded
  std::getline(meta, o.commit);
  std::getline(meta, o.machine);  // absent in outputs saved before it was recorded
  if (o.state == BenchOutcome::State::kIncomplete) o.output.clear();
  if (!o.output_is_json && fs::exists(json)) o.json_file = entry.name + ".json";
  return o;
}

}  // namespace stereoball::bench_report
