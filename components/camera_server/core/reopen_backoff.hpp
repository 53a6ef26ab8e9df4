#pragma once
// Exponential back-off schedule for reopening a lost camera. Time is an argument (ns).

#include <cstdint>
#include <optional>
#include <string>

#include "common/util/result.hpp"

namespace stereoball::camera_server {

/// Back-off shape.
struct BackoffParams {
  double initial_s = 0.5;  ///< wait after the first failure, seconds
  double max_s = 8.0;      ///< longest wait, seconds
  double factor = 2.0;     ///< wait multiplier per consecutive failure

  /// Success, or an error naming the bad field and its allowed range.
  Status validate() const;
};

/// Tracks consecutive failures and when the next attempt is due.
class ReopenBackoff {
 public:
  explicit ReopenBackoff(const BackoffParams& params);

  /// Records a failed attempt (or the loss itself) at now_ns; returns the next attempt time, ns.
  int64_t on_failure(int64_t now_ns);
  /// Records success: the schedule starts again from initial_s.
  void on_success();
  /// True when an attempt may be made at now_ns.
  bool due(int64_t now_ns) const { return now_ns >= next_attempt_ns_; }
  /// Time of the next attempt, ns.
  int64_t next_attempt_ns() const { return next_attempt_ns_; }
  /// Consecutive failures since the last success.
  uint32_t failures() const { return failures_; }

 private:
  BackoffParams params_;
  uint32_t failures_ = 0;
  int64_t next_attempt_ns_ = 0;
};

}  // namespace stereoball::camera_server
