#pragma once
// The measured time between the two eyes' capture stamps of each published pair, summarised
// per health period (camera_server health counters eye_skew_us_p50 / eye_skew_us_max). Pure.

#include <cstdint>
#include <optional>
#include <vector>

namespace stereoball::camera_server {

/// Skew figures of one period, microseconds (|left stamp - right stamp|).
struct EyeSkewSummary {
  uint64_t pairs = 0;   ///< pairs measured in the period
  uint64_t p50_us = 0;  ///< median skew (the upper middle value of an even count)
  uint64_t max_us = 0;  ///< largest skew
};

/// Collects the skew of every pair of a period; take() summarises and starts the next period.
class EyeSkewStats {
 public:
  /// One pair's capture stamps, ns (any single clock).
  void add(int64_t left_stamp_ns, int64_t right_stamp_ns);
  /// The summary of the pairs added since the last take (nullopt when there were none), and a
  /// new period.
  std::optional<EyeSkewSummary> take();

 private:
  std::vector<uint64_t> skews_ns_;
};

}  // namespace stereoball::camera_server
