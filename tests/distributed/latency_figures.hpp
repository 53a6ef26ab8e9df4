#pragma once
// Capture-to-command figures of one run, from what observers printed (observer_log.hpp): per
// frame, the stages between the frame's exposure (StereoFrame.stamp_ns, carried unchanged as
// capture_stamp_ns) and the velocity command that answered its track, plus lost frames and the
// load on the host's cores. Shared by `stereoball bench latency` and its test.

#include <nlohmann/json.hpp>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "observer_log.hpp"

namespace stereoball::distributed {

/// p50/p90/p99/max (linear interpolation) of a set of durations, ms; n = how many.
struct Quantiles {
  double p50 = 0, p90 = 0, p99 = 0, max = 0;
  std::size_t n = 0;
};
Quantiles quantiles(const std::vector<double>& values_ms);

/// The stages of one run. Each frame counts from its exposure; all stamps share one clock.
struct LatencyFigures {
  Quantiles frame_received;  ///< exposure -> the detector took the frame (publish - processing)
  Quantiles detection;       ///< detector took the frame -> ball/detection published
  Quantiles track;           ///< ball/detection published -> ball/track published
  Quantiles command;         ///< ball/track published -> cmd/velocity answering it issued
  Quantiles end_to_end;      ///< exposure -> cmd/velocity answering the frame's track issued
  std::size_t frames_expected = 0;    ///< frame periods between the first and last detection
  std::size_t frames_lost = 0;        ///< of those, frames that never got a detection
  std::size_t tracks_unanswered = 0;  ///< tracks no command carried the capture stamp of
};

/// One frame's way from exposure to command, ms (negative: that stage never happened, e.g. no
/// track or no command answered it).
struct FrameStages {
  std::int64_t capture_ns = 0;
  std::uint64_t seq = 0;
  int detection_status = 0;  ///< ball/detection status (0 = found)
  int track_state = -1;      ///< ball/track state, -1 without a track
  double received_ms = -1, detection_ms = -1, track_ms = -1, command_ms = -1, end_to_end_ms = -1;
};

/// Every detected frame exposed in [from_ns, to_ns), by exposure: detections from
/// detection_log, tracks and commands from control_log (the two may be one observer's log).
std::vector<FrameStages> frame_stages(const ObserverLog& detection_log,
                                      const ObserverLog& control_log, std::int64_t from_ns,
                                      std::int64_t to_ns);

/// Figures of the frames exposed in [from_ns, to_ns) (frame_stages, summarised).
LatencyFigures latency_figures(const ObserverLog& detection_log, const ObserverLog& control_log,
                               std::int64_t from_ns, std::int64_t to_ns, double frame_rate_hz);

/// The host's load over a run: load average, share of all cores busy, our processes' CPU.
struct CoreLoad {
  int cores = 0;
  double load_average_1m = 0;    ///< at the end of the run
  double host_busy_pct = 0;      ///< all cores, everyone's work, % of their time
  double our_processes_pct = 0;  ///< the system under test (+ observers), % of one core
};

/// CPU time counters to take at the start and end of a run (/proc).
struct CpuSample {
  std::int64_t wall_ns = 0;
  unsigned long long host_busy_ticks = 0, host_total_ticks = 0, process_ticks = 0;
};
/// Reads /proc/stat and /proc/PID/stat of pids (and of their children, recursively).
CpuSample cpu_sample(const std::vector<int>& pids);
/// The load between two samples.
CoreLoad core_load(const CpuSample& start, const CpuSample& end);

/// One thread's scheduler counters (/proc/PID/task/TID/schedstat), ns.
struct ThreadTimes {
  std::int64_t run_ns = 0;   ///< on a core
  std::int64_t wait_ns = 0;  ///< runnable, waiting for a core (run queue)
};
/// CPU counters of every program of the system under test at one instant, by program name
/// (the file name of argv[0]: ball_detector, tracker, ...).
struct ProgramCounters {
  unsigned long long ticks = 0;  ///< utime + stime of its processes (exited threads too)
  std::map<std::pair<int, int>, ThreadTimes> threads;  ///< (pid, tid) -> live threads' counters
};
using ProgramSample = std::map<std::string, ProgramCounters>;
/// Reads the programs of pids and their descendants.
ProgramSample program_sample(const std::vector<int>& pids);

/// What one program spent over a run, ms per frame period of the run.
struct ProgramCpu {
  double cpu_ms = 0;       ///< CPU time (user + system) per frame
  double runqueue_ms = 0;  ///< time its threads waited for a core per frame (live threads)
};
/// Each program's CPU and run-queue wait between two samples, divided by frames.
std::map<std::string, ProgramCpu> program_cpu(const ProgramSample& start, const ProgramSample& end,
                                              double frames);
/// One printed line: every program's CPU and run-queue wait per frame.
std::string program_cpu_text(const std::map<std::string, ProgramCpu>& cpu);
/// {"ball_detector": {"cpu_ms": .., "runqueue_wait_ms": ..}, ...}
nlohmann::json program_cpu_json(const std::map<std::string, ProgramCpu>& cpu);

/// {"frame_received_ms": {...}, ..., "end_to_end_ms": {"p50", "p90", "p99", "max", "n"},
///  "frames_expected", "frames_lost", "tracks_unanswered"} plus "load" when given.
nlohmann::json to_json(const LatencyFigures& f, const CoreLoad& load);

/// frames as CSV, a header and one line per frame (for finding what the slow frames were);
/// column measured is 1 for frames exposed at or after measured_from_ns (the window).
std::string to_csv(const std::vector<FrameStages>& frames, std::int64_t measured_from_ns);

/// What the slowest frames end to end (the top share of the measured ones) were: how many,
/// how many had no ball found, and their mean stages, ms.
struct SlowFrames {
  std::size_t n = 0, not_found = 0;
  double received_ms = 0, detection_ms = 0, track_ms = 0, command_ms = 0, end_to_end_ms = 0;
};
/// The frames at or above the (100 - share_pct) percentile end to end, of those answered by a
/// command and exposed at or after from_ns.
SlowFrames slowest_frames(const std::vector<FrameStages>& frames, std::int64_t from_ns,
                          double share_pct);
/// One printed line of s; {"n", "not_found", "received_ms", ...} as JSON.
std::string to_text(const SlowFrames& s, double share_pct);
nlohmann::json to_json(const SlowFrames& s);

/// One printed block: a line per stage, then loss and load.
std::string to_text(const std::string& title, const LatencyFigures& f, const CoreLoad& load);

}  // namespace stereoball::distributed
