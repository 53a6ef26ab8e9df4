#include "chaos_checks.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <limits>

namespace stereoball::bench_chaos {
namespace {

constexpr int kMaxListed = 5;  // violations named in a detail; the rest are counted

std::string seconds(int64_t ns) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", static_cast<double>(ns) * 1e-9);
  return buf;
}

bool moving(const base::BaseEvent& e, const CheckParams& p) {
  return std::abs(e.linear_mps) > p.still_mps || std::abs(e.angular_radps) > p.still_radps;
}

// Collects violations: the first few are described, all are counted.
struct Violations {
  uint64_t count = 0;
  std::string listed;
  void add(const std::string& what) {
    if (count++ < kMaxListed) listed += (listed.empty() ? "" : "; ") + what;
  }
  void finish(CheckResult& r, const std::string& figures) const {
    r.violations = count;
    r.passed = count == 0;
    r.detail = figures;
    if (count > 0) r.detail += "; " + std::to_string(count) + " violation(s): " + listed;
  }
};

}  // namespace

CheckResult check_no_unsafe_motion(std::span<const base::BaseEvent> events, const CheckParams& p) {
  CheckResult r;
  r.name = "no_motion_on_stale_or_unauthenticated_input";
  Violations v;
  uint64_t commands = 0, moving_commands = 0, unsigned_taken = 0, frames = 0, rises = 0;
  int64_t max_moving_age_ns = 0;
  // The robot may speed up until the last fresh authenticated moving command expires (by its
  // own stamp: the simulated base times commands out from their stamp), plus two frame
  // periods of integration between a frame and the command's expiry.
  int64_t allowed_until_ns = std::numeric_limits<int64_t>::min();
  const base::BaseEvent* previous_frame = nullptr;
  for (const auto& e : events) {
    if (e.kind == base::BaseEventKind::kEstop) {
      if (!moving(e, p)) allowed_until_ns = std::numeric_limits<int64_t>::min();
      continue;
    }
    if (e.kind == base::BaseEventKind::kCommand) {
      ++commands;
      const int64_t age_ns = e.time_ns - e.stamp_ns;
      const bool rogue = e.source == p.rogue_source;
      if (p.keyed && !e.authenticated) ++unsigned_taken;
      if (rogue || (p.keyed && !e.authenticated)) {
        v.add("t=" + seconds(e.time_ns) + " the base took command seq " + std::to_string(e.seq) +
              " from '" + e.source + "' (key " + std::to_string(e.key_id) +
              (e.authenticated ? ", verified" : ", not verified") + ")");
      }
      // Any non-zero fresh authenticated command lets the robot speed up (toward it).
      const bool nonzero = e.linear_mps != 0.0 || e.angular_radps != 0.0;
      const bool fresh = age_ns <= p.command_timeout_ns;
      allowed_until_ns = nonzero && fresh && !rogue && (e.authenticated || !p.keyed)
                             ? e.stamp_ns + p.command_timeout_ns
                             : std::numeric_limits<int64_t>::min();
      if (!moving(e, p)) continue;
      ++moving_commands;
      max_moving_age_ns = std::max(max_moving_age_ns, age_ns);
      if (!fresh) {
        v.add("t=" + seconds(e.time_ns) + " the base let through command seq " +
              std::to_string(e.seq) + " aged " + std::to_string(age_ns / 1'000'000) +
              " ms (timeout " + std::to_string(p.command_timeout_ns / 1'000'000) + " ms)");
      }
      continue;
    }
    ++frames;
    if (previous_frame != nullptr) {
      // Speeding up to a speed that counts as moving.
      const bool rose =
          moving(e, p) &&
          (std::abs(e.linear_mps) > std::abs(previous_frame->linear_mps) + p.speed_rise_eps ||
           std::abs(e.angular_radps) > std::abs(previous_frame->angular_radps) + p.speed_rise_eps);
      if (rose) {
        ++rises;
        const bool allowed = allowed_until_ns != std::numeric_limits<int64_t>::min() &&
                             e.time_ns <= allowed_until_ns + 2 * p.frame_period_ns;
        if (!allowed) {
          v.add("t=" + seconds(e.time_ns) + " the robot sped up (" + std::to_string(e.linear_mps) +
                " m/s, " + std::to_string(e.angular_radps) +
                " rad/s) with no fresh authenticated command in force");
        }
      }
    }
    previous_frame = &e;
  }
  char figures[320];
  std::snprintf(figures, sizeof figures,
                "%llu commands executed (%llu moving, oldest moving %.0f ms, %llu unverified); "
                "%llu frames, robot sped up in %llu",
                static_cast<unsigned long long>(commands),
                static_cast<unsigned long long>(moving_commands), max_moving_age_ns * 1e-6,
                static_cast<unsigned long long>(unsigned_taken),
                static_cast<unsigned long long>(frames), static_cast<unsigned long long>(rises));
  r.applicable = commands > 0 || frames > 0;
  v.finish(r, figures);
  return r;
}

CheckResult check_estop_held(std::span<const base::BaseEvent> events, const Timeline& timeline,
                             const CheckParams& p) {
  CheckResult r;
  r.name = "estop_held";
  Violations v;
  uint64_t frames_checked = 0, frames_unaware = 0, commands_blocked = 0;
  int64_t held_ns = 0;
  for (const auto& stop : timeline.estop) {
    const int64_t from = stop.begin_ns + p.estop_grace_ns;
    if (stop.end_ns > from) held_ns += stop.end_ns - from;
    for (const auto& e : events) {
      if (e.time_ns < from || e.time_ns > stop.end_ns) continue;
      if (e.kind != base::BaseEventKind::kFrame) {
        if (moving(e, p)) {
          v.add("t=" + seconds(e.time_ns) + " the base let " + std::to_string(e.linear_mps) +
                " m/s through while the stop was held (engaged at " + seconds(stop.begin_ns) + ")");
        } else if (e.kind == base::BaseEventKind::kCommand) {
          ++commands_blocked;
        }
        continue;
      }
      if (!e.estop_engaged) ++frames_unaware;
      if (e.time_ns < from + p.brake_ns) continue;
      ++frames_checked;
      if (moving(e, p)) {
        v.add("t=" + seconds(e.time_ns) + " the robot moved (" + std::to_string(e.linear_mps) +
              " m/s, " + std::to_string(e.angular_radps) + " rad/s) while the stop was held");
      }
    }
  }
  char figures[320];
  std::snprintf(figures, sizeof figures,
                "%zu stops held %.1f s in all; %llu frames checked standing, %llu commands "
                "blocked, %llu frames before the base had learned the stop",
                timeline.estop.size(), held_ns * 1e-9,
                static_cast<unsigned long long>(frames_checked),
                static_cast<unsigned long long>(commands_blocked),
                static_cast<unsigned long long>(frames_unaware));
  r.applicable = !timeline.estop.empty();
  v.finish(r, figures);
  return r;
}

TopicLoss count_losses(const std::string& topic, std::span<const SeqSample> samples,
                       std::span<const Interval> excused) {
  TopicLoss loss{topic};
  const SeqSample* previous = nullptr;
  uint64_t run_first = 0;
  auto close_run = [&] {
    if (previous != nullptr) loss.published += previous->seq - run_first + 1;
  };
  for (const auto& s : samples) {
    if (previous == nullptr || s.seq < previous->seq) {
      // A new publisher run: its numbering starts again.
      close_run();
      ++loss.publisher_runs;
      run_first = s.seq;
      ++loss.recorded;
      previous = &s;
      continue;
    }
    if (s.seq == previous->seq) {
      ++loss.duplicates;
      continue;
    }
    ++loss.recorded;
    const uint64_t missing = s.seq - previous->seq - 1;
    if (missing > 0) {
      const bool link_down = std::any_of(excused.begin(), excused.end(), [&](const Interval& i) {
        return i.overlaps(previous->log_time_ns, s.log_time_ns);
      });
      (link_down ? loss.lost_link_down : loss.lost) += missing;
    }
    previous = &s;
  }
  close_run();
  return loss;
}

CheckResult check_none_lost(std::span<const TopicLoss> topics) {
  CheckResult r;
  r.name = "none_lost";
  Violations v;
  std::string figures;
  for (const auto& t : topics) {
    char buf[256];
    std::snprintf(
        buf, sizeof buf, "%s%s published %llu recorded %llu lost %llu (%llu link down)",
        figures.empty() ? "" : "; ", t.topic.c_str(), static_cast<unsigned long long>(t.published),
        static_cast<unsigned long long>(t.recorded), static_cast<unsigned long long>(t.lost),
        static_cast<unsigned long long>(t.lost_link_down));
    figures += buf;
    if (t.lost > 0) v.add(t.topic + ": " + std::to_string(t.lost) + " sample(s) never recorded");
    if (t.lost > 0) v.count += t.lost - 1;  // count samples, not topics
  }
  r.applicable = !topics.empty();
  v.finish(r, figures);
  return r;
}

SettledGrowth settled_growth(const MemorySpan& span, const MemoryRule& rule) {
  SettledGrowth g;
  if (span.samples.empty()) return g;
  const int64_t from = span.started_ns + rule.settle_ns;
  const int64_t last = span.samples.back().t_ns;
  const int64_t to = last - rule.window_ns;  // the last window is (to, last]
  if (to < from + rule.window_ns) return g;  // the two windows would overlap
  // The lowest sample of each window: a spike, or work that comes and goes (the simulator's
  // memory alternates between two levels about 6 MB apart every 20 s, the length of its looping
  // scenario), is no growth, while a leak raises the floor too.
  long first_low = LONG_MAX, last_low = LONG_MAX;
  for (const auto& s : span.samples) {
    if (s.t_ns >= from && s.t_ns < from + rule.window_ns) first_low = std::min(first_low, s.kb);
    if (s.t_ns > to) last_low = std::min(last_low, s.kb);
  }
  if (first_low == LONG_MAX || last_low == LONG_MAX) return g;
  g.available = true;
  g.from_ns = from + rule.window_ns / 2;
  g.to_ns = last - rule.window_ns / 2;
  g.from_kb = first_low;
  g.to_kb = last_low;
  return g;
}

CheckResult check_memory(std::span<const MemorySpan> spans, const MemoryRule& rule) {
  CheckResult r;
  r.name = "memory_growth";
  Violations v;
  uint64_t judged = 0;
  double largest = -1e9, largest_start_end = -1e9;
  for (const auto& s : spans) {
    const SettledGrowth g = settled_growth(s, rule);
    if (!g.available || g.to_ns - g.from_ns < rule.min_span_ns) continue;
    ++judged;
    largest = std::max(largest, g.percent());
    largest_start_end = std::max(largest_start_end, s.growth_percent());
    if (g.percent() > rule.max_growth_percent) {
      char buf[240];
      std::snprintf(buf, sizeof buf,
                    "%s (pid %d) grew %.1f %% after settling (%ld -> %ld kB over %.0f s; start "
                    "-> end %+.1f %%)",
                    s.process.c_str(), s.pid, g.percent(), g.from_kb, g.to_kb,
                    (g.to_ns - g.from_ns) * 1e-9, s.growth_percent());
      v.add(buf);
    }
  }
  char figures[300];
  if (judged > 0) {
    std::snprintf(
        figures, sizeof figures,
        "%llu process instance(s) settled for at least %.0f s judged against %.1f %% "
        "(lowest VmRSS of a %.0f s window from %.0f s after each start -> of the last): largest "
        "%+.1f %%; their start -> end growth (not judged) up to %+.1f %%",
        static_cast<unsigned long long>(judged), rule.min_span_ns * 1e-9, rule.max_growth_percent,
        rule.window_ns * 1e-9, rule.settle_ns * 1e-9, largest, largest_start_end);
  } else {
    std::snprintf(figures, sizeof figures,
                  "no process instance settled for %.0f s (%.0f s after its start)",
                  rule.min_span_ns * 1e-9, rule.settle_ns * 1e-9);
  }
  r.applicable = judged > 0;
  v.finish(r, figures);
  return r;
}

CheckResult check_no_crashes(const std::vector<std::string>& unexpected_exits) {
  CheckResult r;
  r.name = "no_unexpected_exits";
  Violations v;
  for (const auto& e : unexpected_exits) v.add(e);
  v.finish(r, "nodes exit only when the run kills them");
  return r;
}

Result<uint64_t> cdr_leading_u64(std::span<const uint8_t> cdr) {
  if (cdr.size() < 12) return Error{"CDR sample too short for a leading uint64"};
  const unsigned id = (static_cast<unsigned>(cdr[0]) << 8) | cdr[1];
  // Plain CDR (0x0000/0x0001) and XCDR2 final types (0x0006/0x0007): no header before the
  // first member; the low bit is the byte order (1 = little-endian).
  if (id != 0x0000 && id != 0x0001 && id != 0x0006 && id != 0x0007)
    return Error{"CDR encapsulation " + std::to_string(id) + " not plain"};
  uint64_t value = 0;
  for (int i = 0; i < 8; ++i) {
    const uint64_t byte = cdr[4 + i];
    value |= (id & 1) ? byte << (8 * i) : byte << (8 * (7 - i));
  }
  return value;
}

}  // namespace stereoball::bench_chaos
