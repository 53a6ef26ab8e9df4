#pragma once
// Clocks for benchmarks (tools and bench programs only: cores take time as an argument).

#include <time.h>

#include <chrono>

namespace stereoball::bench {

/// CPU time of the calling thread, ms: with one OpenCV thread it is the single-core cost, and
/// unlike wall time it does not grow when other processes load the machine.
inline double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

/// Monotonic wall clock, ms.
inline double wall_ms() {
  return std::chrono::duration<double, std::milli>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace stereoball::bench
