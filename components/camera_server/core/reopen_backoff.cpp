#include "camera_server/core/reopen_backoff.hpp"

#include <algorithm>
#include <cmath>

namespace stereoball::camera_server {

Status BackoffParams::validate() const {
  if (!(initial_s > 0.0 && initial_s <= 60.0)) {
    return Error{"initial_s must be in (0, 60], got " + std::to_string(initial_s)};
  }
  if (!(max_s >= initial_s && max_s <= 600.0)) {
    return Error{"max_s must be in [initial_s, 600], got " + std::to_string(max_s)};
  }
  if (!(factor >= 1.0 && factor <= 10.0)) {
    return Error{"factor must be in [1, 10], got " + std::to_string(factor)};
  }
  return {};
}

ReopenBackoff::ReopenBackoff(const BackoffParams& params) : params_(params) {}

int64_t ReopenBackoff::on_failure(int64_t now_ns) {
  const double wait_s =
      std::min(params_.max_s, params_.initial_s * std::pow(params_.factor, failures_));
  ++failures_;
  next_attempt_ns_ = now_ns + static_cast<int64_t>(std::llround(wait_s * 1e9));
  return next_attempt_ns_;
}

void ReopenBackoff::on_success() {
  failures_ = 0;
  next_attempt_ns_ = 0;
}

}  // namespace stereoball::camera_server
