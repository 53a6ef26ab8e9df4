#pragma once
// Pairs left and right frames whose capture stamps differ by at most a skew; frames that can
// never be paired are dropped and counted. Payload-agnostic (raw bytes, cv::Mat, ids in tests).

#include <cstdint>
#include <cstdlib>
#include <deque>
#include <optional>
#include <string>
#include <utility>

#include "common/util/result.hpp"

namespace stereoball::camera_server {

/// Which camera a frame came from.
enum class Eye { kLeft = 0, kRight = 1 };

/// Short name of an eye ("left"/"right").
inline const char* eye_name(Eye eye) {
  return eye == Eye::kLeft ? "left" : "right";
}

/// One captured frame of one eye; stamp_ns is the driver capture stamp (any single clock).
template <typename T>
struct EyeFrame {
  Eye eye = Eye::kLeft;
  int64_t stamp_ns = 0;
  T payload{};
};

/// A synchronized pair; stamp_ns is the mean of both capture stamps.
template <typename T>
struct StereoPair {
  uint64_t seq = 0;  ///< pair counter, starts at 0
  int64_t stamp_ns = 0;
  int64_t left_stamp_ns = 0;
  int64_t right_stamp_ns = 0;
  T left{};
  T right{};
};

/// Pairing tolerances.
struct PairerParams {
  int64_t max_skew_ns = 16'666'667;  ///< largest |left - right| stamp difference, ns
  uint32_t max_pending = 4;          ///< frames held per eye while waiting for a partner

  /// Success, or an error naming the bad field and its allowed range.
  Status validate() const {
    if (max_skew_ns <= 0)
      return Error{"max_skew_ns must be > 0, got " + std::to_string(max_skew_ns)};
    if (max_pending < 1 || max_pending > 64) {
      return Error{"max_pending must be in [1, 64], got " + std::to_string(max_pending)};
    }
    return {};
  }
};

/// Totals since construction.
struct PairerStats {
  uint64_t pairs = 0;
  uint64_t dropped_left = 0;   ///< left frames that never found a partner
  uint64_t dropped_right = 0;  ///< right frames that never found a partner
};

/// Stateful pairer; feed every frame of both eyes in arrival order.
template <typename T>
class StereoPairer {
 public:
  /// Outcome of one step: a pair when one completed, and frames dropped by this step.
  struct StepResult {
    std::optional<StereoPair<T>> pair;
    uint32_t dropped = 0;
  };

  explicit StereoPairer(const PairerParams& params) : params_(params) {}

  /// Adds one frame; returns the completed pair (if any) and the frames dropped now.
  StepResult step(EyeFrame<T> frame) {
    StepResult out;
    auto& mine = queue(frame.eye);
    auto& other = queue(other_eye(frame.eye));
    const int64_t t = frame.stamp_ns;
    auto best = other.end();
    for (auto it = other.begin(); it != other.end(); ++it) {
      const int64_t d = std::llabs(it->stamp_ns - t);
      if (d <= params_.max_skew_ns && (best == other.end() || d < std::llabs(best->stamp_ns - t))) {
        best = it;
      }
    }
    if (best != other.end()) {
      // Everything older than the matched frames can only pair with frames already gone.
      out.dropped += drop_front(other, static_cast<size_t>(best - other.begin()));
      EyeFrame<T> partner = std::move(other.front());
      other.pop_front();
      out.dropped += drop_front(mine, mine.size());
      out.pair = make_pair(std::move(frame), std::move(partner));
      return out;
    }
    // Partners older than t - skew can never match this or any later frame of this eye.
    size_t stale = 0;
    while (stale < other.size() && other[stale].stamp_ns < t - params_.max_skew_ns) ++stale;
    out.dropped += drop_front(other, stale);
    mine.push_back(std::move(frame));
    if (mine.size() > params_.max_pending) out.dropped += drop_front(mine, 1);
    return out;
  }

  /// Discards held frames (e.g. when a camera is reopened), counting them as dropped.
  uint32_t flush() {
    return drop_front(queue(Eye::kLeft), queue(Eye::kLeft).size()) +
           drop_front(queue(Eye::kRight), queue(Eye::kRight).size());
  }

  /// Totals since construction.
  const PairerStats& stats() const { return stats_; }

 private:
  static Eye other_eye(Eye e) { return e == Eye::kLeft ? Eye::kRight : Eye::kLeft; }
  std::deque<EyeFrame<T>>& queue(Eye e) { return queues_[static_cast<int>(e)]; }

  uint32_t drop_front(std::deque<EyeFrame<T>>& q, size_t n) {
    for (size_t i = 0; i < n; ++i) {
      (q.front().eye == Eye::kLeft ? stats_.dropped_left : stats_.dropped_right)++;
      q.pop_front();
    }
    return static_cast<uint32_t>(n);
  }

  StereoPair<T> make_pair(EyeFrame<T> a, EyeFrame<T> b) {
    EyeFrame<T>& l = a.eye == Eye::kLeft ? a : b;
    EyeFrame<T>& r = a.eye == Eye::kLeft ? b : a;
    StereoPair<T> p;
    p.seq = stats_.pairs++;
    p.left_stamp_ns = l.stamp_ns;
    p.right_stamp_ns = r.stamp_ns;
    p.stamp_ns = l.stamp_ns + (r.stamp_ns - l.stamp_ns) / 2;
    p.left = std::move(l.payload);
    p.right = std::move(r.payload);
    return p;
  }

  PairerParams params_;
  PairerStats stats_;
  std::deque<EyeFrame<T>> queues_[2];
};

}  // namespace stereoball::camera_server
