#pragma once
// The checks of `stereoball bench chaos`, over event logs: what the robot base executed (its
// base log, base/core/base_log.hpp), what the chaos run did and when (its timeline), the
// sequence numbers recorded by `stereoball record`, and memory samples. Pure: no clocks, no
// I/O; every time is an argument (ns since the epoch, one host's clock).

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "base/core/base_log.hpp"
#include "common/util/result.hpp"

namespace stereoball::bench_chaos {

/// A span of time, begin_ns <= end_ns.
struct Interval {
  int64_t begin_ns = 0;
  int64_t end_ns = 0;
  bool contains(int64_t t_ns) const { return t_ns >= begin_ns && t_ns <= end_ns; }
  bool overlaps(int64_t a_ns, int64_t b_ns) const { return a_ns <= end_ns && b_ns >= begin_ns; }
};

/// What the chaos run did, on its own clock.
struct Timeline {
  /// E-stop held: from the moment `estop engage` returned (the stop was published) to the
  /// moment `estop release` was started.
  std::vector<Interval> estop;
  std::vector<Interval> link_cuts;  ///< link between the namespaces down
  std::vector<Interval> floods;     ///< garbage on stereo/frame
  std::vector<Interval> rogue;      ///< commands signed with a key the deployment does not know
};

struct CheckParams {
  int64_t command_timeout_ns = 300'000'000;  ///< the base's command timeout
  int64_t frame_period_ns = 33'333'333;      ///< the simulator's frame period
  /// After `estop engage` returned, the base must hold it within this (a restarted simulator
  /// learning the latched stop included).
  int64_t estop_grace_ns = 500'000'000;
  /// Braking from full speed to standing, at the simulated base's limits (1 m/s at 4 m/s^2).
  int64_t brake_ns = 400'000'000;
  double still_mps = 1e-3;       ///< |linear| below this is standing still
  double still_radps = 1e-3;     ///< |angular| below this is standing still
  double speed_rise_eps = 1e-6;  ///< speed rising by more than this between frames: driven
  /// Seq gaps of a topic published across the link are excused while the link is down and
  /// this long after it is restored (reliable history is finite; discovery again).
  int64_t link_settle_ns = 5'000'000'000;
  std::string rogue_source = "chaos-rogue";  ///< source field of the rogue's commands
  bool keyed = true;  ///< the deployment runs with a key (every executed command must be signed)
};

/// Verdict of one check, with its figures.
struct CheckResult {
  std::string name;
  bool passed = true;
  bool applicable = true;  ///< false: nothing to judge (e.g. no e-stop engaged); passes
  std::string detail;      ///< figures and, on failure, the first violations
  uint64_t violations = 0;
};

/// The base never executed an unauthenticated command, a rogue's command, or motion from a
/// command older than the timeout; the robot never sped up without a fresh authenticated
/// command in force.
CheckResult check_no_unsafe_motion(std::span<const base::BaseEvent> events,
                                   const CheckParams& params);
/// While the e-stop was held (after the grace), the base let no velocity through and the robot
/// (after braking) stood still.
CheckResult check_estop_held(std::span<const base::BaseEvent> events, const Timeline& timeline,
                             const CheckParams& params);

/// One recorded sample of a topic whose publisher numbers its samples.
struct SeqSample {
  uint64_t seq = 0;
  int64_t log_time_ns = 0;  ///< when the recorder received it
};

/// Published (from the sequence numbers) against recorded for one topic.
struct TopicLoss {
  std::string topic;
  uint64_t publisher_runs = 0;  ///< the seq restarted (publisher restarted) this many times + 1
  uint64_t published = 0;       ///< sum over runs of last - first + 1
  uint64_t recorded = 0;        ///< distinct samples in the recording
  uint64_t duplicates = 0;
  uint64_t lost = 0;            ///< missing while nothing excused it
  uint64_t lost_link_down = 0;  ///< missing while the link was down (or settling)
};

/// Splits samples (file order) into publisher runs where the seq falls back, counts the gaps;
/// a gap whose neighbours' receive times overlap an excused interval counts as lost_link_down.
TopicLoss count_losses(const std::string& topic, std::span<const SeqSample> samples,
                       std::span<const Interval> excused);
/// Passes when no topic lost a sample outside the excused intervals.
CheckResult check_none_lost(std::span<const TopicLoss> topics);

/// One VmRSS sample of a process instance.
struct MemorySample {
  int64_t t_ns = 0;
  long kb = 0;
};

/// VmRSS of one process instance: its first sample (after warm-up), its last, and every one.
struct MemorySpan {
  std::string process;
  int pid = 0;
  int64_t first_ns = 0, last_ns = 0;
  long first_kb = 0, last_kb = 0;
  int64_t started_ns = 0;             ///< when the instance was started
  std::vector<MemorySample> samples;  ///< every sample, in time order
  /// Start -> end: first sample to last sample.
  double growth_percent() const {
    return first_kb > 0 ? 100.0 * static_cast<double>(last_kb - first_kb) / first_kb : 0.0;
  }
};

/// How memory is judged: growth after a settle window, between the lowest samples of two
/// short windows.
struct MemoryRule {
  int64_t settle_ns = 120'000'000'000;    ///< from the instance's start: its working set forms
  int64_t window_ns = 60'000'000'000;     ///< samples whose median stands for one end
  int64_t min_span_ns = 300'000'000'000;  ///< settled span an instance needs to be judged
  double max_growth_percent = 5.0;
};

/// Growth of one instance after it settled: the lowest of its samples in [start + settle,
/// start + settle + window) against the lowest of its samples in the last window.
struct SettledGrowth {
  bool available = false;          ///< false when the instance did not live past settle + window
  int64_t from_ns = 0, to_ns = 0;  ///< middle of the first and of the last window
  long from_kb = 0, to_kb = 0;
  double percent() const {
    return from_kb > 0 ? 100.0 * static_cast<double>(to_kb - from_kb) / from_kb : 0.0;
  }
};
SettledGrowth settled_growth(const MemorySpan& span, const MemoryRule& rule);

/// Passes when every instance whose settled span lasted at least rule.min_span_ns grew by at
/// most rule.max_growth_percent after settling; the start -> end figures are printed beside
/// (never judged). Shorter-lived instances are listed but not judged.
CheckResult check_memory(std::span<const MemorySpan> spans, const MemoryRule& rule);

/// Passes when no node exited without being killed by the run (a crash on garbage, say).
CheckResult check_no_crashes(const std::vector<std::string>& unexpected_exits);

/// The first 8 bytes of a CDR sample's payload (after the 4-byte encapsulation header) as an
/// unsigned integer in the sample's byte order: the seq of a message that starts with one.
Result<uint64_t> cdr_leading_u64(std::span<const uint8_t> cdr);

}  // namespace stereoball::bench_chaos
