#pragma once
// The two clocks of the system, for the DDS layer and the node runner (cores take time as an
// argument instead).

#include <chrono>
#include <cstdint>

namespace stereoball::util {

/// Wall-clock time, ns since epoch (the stamps of every message).
inline int64_t wall_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

/// Monotonic time, ns (for intervals).
inline int64_t monotonic_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace stereoball::util
