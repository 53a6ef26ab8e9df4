#pragma once
// Moving a stamp from the monotonic clock (V4L2 buffers, timers) to the epoch clock that every
// message carries (CLOCK_REALTIME, ns since the Unix epoch). Pure: the clocks are arguments.

#include <cstdint>

namespace stereoball {

/// stamp_monotonic_ns on the epoch clock, given both clocks read at one instant (now_*): the
/// stamp keeps its distance to "now", in integer ns (no rounding through floating point).
constexpr std::int64_t monotonic_to_epoch_ns(std::int64_t stamp_monotonic_ns,
                                             std::int64_t now_monotonic_ns,
                                             std::int64_t now_epoch_ns) {
  return now_epoch_ns - (now_monotonic_ns - stamp_monotonic_ns);
}

}  // namespace stereoball
