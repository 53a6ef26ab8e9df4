#include "viewer/core/flow.hpp"

#include <algorithm>
#include <cmath>

namespace stereoball::viewer {

namespace {

constexpr double kBurst = 2;  // events that may pass back to back after a pause
// An event may pass with this much credit: one arriving 10 % of an interval early (jitter)
// borrows the rest from the next interval instead of being lost.
constexpr double kEnough = 0.9;

}  // namespace

RateLimiter::RateLimiter(double max_rate_hz)
    : interval_ns_(max_rate_hz > 0 ? static_cast<int64_t>(1e9 / max_rate_hz) : 0) {}

double RateLimiter::credit_at(int64_t now_ns) const {
  if (!last_ns_) return kBurst;
  const double earned = static_cast<double>(now_ns - *last_ns_) / static_cast<double>(interval_ns_);
  return std::min(kBurst, credit_ + std::max(0.0, earned));
}

bool RateLimiter::admit(int64_t now_ns) {
  if (interval_ns_ == 0) return true;
  const double credit = credit_at(now_ns);
  credit_ = credit;
  last_ns_ = now_ns;
  if (credit < kEnough) return false;
  credit_ = credit - 1;
  return true;
}

int64_t RateLimiter::wait_ns(int64_t now_ns) const {
  if (interval_ns_ == 0) return 0;
  const double missing = kEnough - credit_at(now_ns);
  return missing <= 0 ? 0 : static_cast<int64_t>(std::ceil(missing * interval_ns_));
}

Status FlowParams::validate() const {
  if (max_frames_in_flight < 1 || max_frames_in_flight > 16)
    return Error{"max_frames_in_flight must be in 1..16"};
  if (drop_images_above_bytes < 1024) return Error{"drop_images_above_bytes must be >= 1024"};
  if (disconnect_above_bytes <= drop_images_above_bytes)
    return Error{"disconnect_above_bytes must be larger than drop_images_above_bytes"};
  if (stall_timeout_ns <= 0) return Error{"stall_timeout_ns must be > 0"};
  return {};
}

ClientFlow::ClientFlow(const FlowParams& params, bool acks) : params_(params), acks_(acks) {}

bool ClientFlow::stalled(uint64_t queued_bytes, int64_t now_ns) {
  if (queued_bytes > params_.disconnect_above_bytes) return true;
  if (queued_bytes <= params_.drop_images_above_bytes) {
    over_limit_since_ns_.reset();
    return false;
  }
  if (!over_limit_since_ns_) over_limit_since_ns_ = now_ns;
  return now_ns - *over_limit_since_ns_ >= params_.stall_timeout_ns;
}

bool ClientFlow::ready_for_image(uint64_t queued_bytes) const {
  return queued_bytes <= params_.drop_images_above_bytes &&
         !(acks_ && in_flight_ >= params_.max_frames_in_flight);
}

Decision ClientFlow::offer_image(uint64_t queued_bytes, int64_t now_ns) {
  if (stalled(queued_bytes, now_ns)) return Decision::kDisconnect;
  if (!ready_for_image(queued_bytes)) {
    ++dropped_images_;
    return Decision::kDrop;
  }
  ++sent_images_;
  if (acks_) ++in_flight_;
  return Decision::kSend;
}

Decision ClientFlow::offer_scene(uint64_t queued_bytes, int64_t now_ns) {
  if (stalled(queued_bytes, now_ns)) return Decision::kDisconnect;
  if (acks_ && scene_in_flight_) return Decision::kDrop;
  if (acks_) scene_in_flight_ = true;
  return Decision::kSend;
}

Decision ClientFlow::offer_message(uint64_t queued_bytes, int64_t now_ns) {
  return stalled(queued_bytes, now_ns) ? Decision::kDisconnect : Decision::kSend;
}

void ClientFlow::on_ack() {
  if (in_flight_ > 0) --in_flight_;
}

}  // namespace stereoball::viewer
