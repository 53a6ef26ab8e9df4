#pragma once
// The fault schedule of `stereoball bench chaos`: seeded, so a run can be repeated. Pure.

#include <cstdint>
#include <string_view>
#include <vector>

namespace stereoball::bench_chaos {

enum class FaultKind {
  kKillNode,       ///< kill a node (SIGKILL or SIGTERM), restart it after the duration
  kCutLink,        ///< take the link between the namespaces down for the duration
  kFloodFrames,    ///< publish garbage on stereo/frame for the duration
  kRotateKey,      ///< `stereoball keys rotate` on the deployment key file
  kEstop,          ///< engage the e-stop, release it after the duration
  kRogueCommands,  ///< publish commands signed with an unknown key for the duration
};
std::string_view to_string(FaultKind kind);

struct Fault {
  int64_t at_ns = 0;  ///< start, from the beginning of the faults
  FaultKind kind = FaultKind::kKillNode;
  int64_t duration_ns = 0;  ///< how long it lasts (kill: until the restart)
  int node = 0;             ///< kKillNode: index of the node
  bool sigkill = false;     ///< kKillNode: SIGKILL (else SIGTERM)
};

struct PlanParams {
  int64_t span_ns = 60'000'000'000;     ///< faults start within [0, span)
  int64_t mean_gap_ns = 8'000'000'000;  ///< mean quiet time between two faults (exponential)
  int64_t min_gap_ns = 2'000'000'000;   ///< at least this quiet time between two faults
  int nodes = 4;                        ///< nodes that may be killed
  bool link = true;                     ///< kCutLink possible (namespaces available)
};

/// Faults in time order, one at a time (each ends before the next starts); every kind
/// available appears at least once when the span allows it (first a round in a seeded order,
/// then random kinds).
std::vector<Fault> plan_faults(const PlanParams& params, uint64_t seed);

/// The leading faults of plan up to (not including) the first whose kind came before: one of
/// each kind when the plan's span held its first round.
std::vector<Fault> first_round(const std::vector<Fault>& plan);

}  // namespace stereoball::bench_chaos
