#pragma once
// Flow control between the viewer and its clients, so a slow or stuck client costs only its
// own frames: a rate limit for encoding, and per-client decisions to send, drop or disconnect.

#include <cstdint>
#include <optional>
#include <string>

#include "common/util/result.hpp"

namespace stereoball::viewer {

/// Passes events at no more than a rate on average (a token bucket; time as an argument). A
/// source at the rate passes whole even with jitter: an early event spends credit that the
/// next, later one makes up, and up to two events may pass back to back after a pause.
class RateLimiter {
 public:
  /// max_rate_hz <= 0 passes everything.
  explicit RateLimiter(double max_rate_hz);
  /// True when an event at now_ns may pass (and spends its credit).
  bool admit(int64_t now_ns);
  /// Nanoseconds from now_ns until an event may pass (0: now). A source that can wait, as the
  /// viewer's frame reader can (keep-last-1 keeps the newest frame meanwhile), waits this long
  /// instead of losing the event.
  int64_t wait_ns(int64_t now_ns) const;

 private:
  double credit_at(int64_t now_ns) const;
  int64_t interval_ns_;  // 0: no limit
  double credit_ = 0;    // events that may pass, as of last_ns_ (unset: a full bucket)
  std::optional<int64_t> last_ns_;
};

/// Limits of one client's outgoing queue.
struct FlowParams {
  uint32_t max_frames_in_flight = 2;            ///< images sent but not yet drawn (browser acks)
  uint64_t drop_images_above_bytes = 1u << 20;  ///< queued bytes above which images are dropped
  uint64_t disconnect_above_bytes = 16u << 20;  ///< queued bytes above which the client is cut off
  int64_t stall_timeout_ns = 5'000'000'000;     ///< over the drop limit this long: cut off
  /// Success, or an error naming the bad field and its allowed range.
  Status validate() const;
};

enum class Decision { kSend, kDrop, kDisconnect };

/// Per-client send policy. Images are the only messages worth dropping (a newer one follows);
/// everything else is small and is sent unless the client is so far behind that it is cut off.
class ClientFlow {
 public:
  /// acks: the client acknowledges each image it has drawn (the page does; Foxglove does not).
  ClientFlow(const FlowParams& params, bool acks);
  /// Whether to send an image now, given the bytes still queued for this client.
  Decision offer_image(uint64_t queued_bytes, int64_t now_ns);
  /// True when offer_image would send now (a free slot, backlog under the drop limit): the
  /// viewer encodes a frame only while some client would take it.
  bool ready_for_image(uint64_t queued_bytes) const;
  /// Whether to send a scene (state replaced by the next one) now: with acks, only when the
  /// previous scene was acknowledged, so scenes never queue up in a slow page.
  Decision offer_scene(uint64_t queued_bytes, int64_t now_ns);
  /// Whether to send any other message now.
  Decision offer_message(uint64_t queued_bytes, int64_t now_ns);
  /// The client drew an image (frees one slot in flight).
  void on_ack();
  /// The client took in the last scene.
  void on_scene_ack() { scene_in_flight_ = false; }
  uint64_t sent_images() const { return sent_images_; }
  uint64_t dropped_images() const { return dropped_images_; }
  uint32_t in_flight() const { return in_flight_; }

 private:
  bool stalled(uint64_t queued_bytes, int64_t now_ns);
  FlowParams params_;
  bool acks_;
  uint32_t in_flight_ = 0;
  bool scene_in_flight_ = false;
  uint64_t sent_images_ = 0;
  uint64_t dropped_images_ = 0;
  std::optional<int64_t> over_limit_since_ns_;
};

}  // namespace stereoball::viewer
