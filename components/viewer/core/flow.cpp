#include "viewer/core/flow.hpp"

namespace stereoball::viewer {

RateLimiter::RateLimiter(double max_rate_hz)
    : min_interval_ns_(max_rate_hz > 0 ? static_cast<int64_t>(1e9 / max_rate_hz) : 0) {}

bool RateLimiter::admit(int64_t now_ns) {
  // A small tolerance keeps a source at exactly the limit from losing every other event to
  // jitter in its arrival times.
  const int64_t tolerance_ns = min_interval_ns_ / 10;
  if (last_ns_ && now_ns - *last_ns_ < min_interval_ns_ - tolerance_ns) return false;
  last_ns_ = now_ns;
  return true;
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
