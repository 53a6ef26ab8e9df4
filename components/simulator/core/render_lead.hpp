#pragma once
// How long before its exposure instant the simulator starts a frame's work (render, encode,
// message), so the frame is ready at that instant and no earlier than it needs to be: the
// recent frames' work (its 90th percentile) plus a margin. A lead measured once at start-up, beside
// the other nodes starting, came out anywhere between a third of a period and a whole one; a
// lead near the period puts the next frame's render (two threads) right beside the current
// frame's detection, the work the simulator stands in front of.

#include <cstdint>
#include <deque>

namespace stereoball::simulator {

/// The render lead from the work times of the last window_frames frames (ns, monotonic).
class RenderLead {
 public:
  /// initial_ns until the first frame's work is known; leads stay within [kMarginNs,
  /// period_ns - kMarginNs / 2]; window_frames >= 1 (about a second of frames).
  RenderLead(int64_t initial_ns, int64_t period_ns, int window_frames);

  /// One frame's work (from its start to ready to release), ns; negative values are ignored.
  void add_work(int64_t work_ns);

  /// The lead now: the window's 90th percentile of work x 5/4 + kMarginNs, clamped.
  int64_t lead_ns() const { return lead_ns_; }

  /// Lowest and highest lead so far (the initial one included).
  int64_t min_lead_ns() const { return min_lead_ns_; }
  int64_t max_lead_ns() const { return max_lead_ns_; }

  /// Time for the timer to wake and the loop to run the frame's work.
  static constexpr int64_t kMarginNs = 2'000'000;

  /// lead for the work work_ns within a period of period_ns.
  static int64_t lead_for(int64_t work_ns, int64_t period_ns);

 private:
  int64_t period_ns_;
  std::size_t window_frames_;
  std::deque<int64_t> work_ns_;
  int64_t lead_ns_;
  int64_t min_lead_ns_;
  int64_t max_lead_ns_;
};

}  // namespace stereoball::simulator
