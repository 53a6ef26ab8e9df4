#pragma once
// The chaos run's child modes: this program started again (--child) to flood stereo/frame with
// garbage or to send velocity commands signed with a key the deployment does not know.

#include <cstdint>

#include "chaos_run.hpp"

namespace stereoball::bench_chaos {

// The rogue's commands carry seq from here on, so the recording tells them apart.
constexpr uint64_t kRogueSeqBase = uint64_t{1} << 62;

/// Garbage stereo/frame samples every 5 ms for o.child_seconds (or until g_stop); exit code.
int run_flood(const Options& o);
/// Velocity commands from kRogueSeqBase every 20 ms for o.child_seconds (or until g_stop).
int run_rogue(const Options& o);

}  // namespace stereoball::bench_chaos
