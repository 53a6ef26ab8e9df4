// ddsperf's per-second ping lines, summarised the way bench transport summarises its own pings.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace stereoball::bench_transport {

// A second with fewer round trips than this has no meaningful 99th percentile: its line counts
// toward the rate but not toward the latency figures (the same rule for both sides).
inline constexpr size_t kMinSamplesPerSecond = 10;

// What a ddsperf ping log holds after its first line (discovery and warm-up).
struct DdsperfSeconds {
  std::vector<double> medians_us;  // 50 % of each second with enough round trips
  std::vector<double> p99s_us;     // 99 % of the same seconds
  size_t count = 0;                // round trips in every second after the first
  size_t seconds = 0;              // per-second lines after the first
  size_t sparse_seconds = 0;       // of these, with fewer than kMinSamplesPerSecond round trips
};

// Reads the lines "... size S mean ..us min ..us 50% Xus 90% ..us 99% Yus max ..us cnt N" of a
// ddsperf ping log; other lines are ignored.
DdsperfSeconds parse_ddsperf_ping_log(const std::string& log);

}  // namespace stereoball::bench_transport
