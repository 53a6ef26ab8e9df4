#pragma once
// Frames per second over a measurement, from the frame numbers of the samples received and
// their receive times. Pure: the caller supplies the samples and guards concurrent use.

#include <cstdint>

namespace stereoball::bench {

class FrameCount {
 public:
  /// A frame numbered seq was received at now_ns.
  void sample(uint64_t seq, int64_t now_ns) {
    last_seq_ = seq;
    last_ns_ = now_ns;
    if (!have_start_) {  // nothing had arrived when the measurement began: it begins here
      start_seq_ = seq;
      start_ns_ = now_ns;
      have_start_ = true;
    }
    have_last_ = true;
  }
  /// Marks the start of a measurement: the newest frame so far, or the next one to arrive.
  void restart() {
    start_seq_ = last_seq_;
    start_ns_ = last_ns_;
    have_start_ = have_last_;
  }
  /// Frames per second between the start and the newest frame; 0 before two frames apart.
  double rate_hz() const {
    const int64_t dt = last_ns_ - start_ns_;
    if (!have_start_ || dt <= 0 || last_seq_ < start_seq_) return 0.0;
    return static_cast<double>(last_seq_ - start_seq_) / (static_cast<double>(dt) / 1e9);
  }

 private:
  uint64_t last_seq_ = 0, start_seq_ = 0;
  int64_t last_ns_ = 0, start_ns_ = 0;
  bool have_last_ = false, have_start_ = false;
};

}  // namespace stereoball::bench
