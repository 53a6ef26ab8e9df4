#include "ball_detector/node/frame_gaps.hpp"

namespace stereoball::ball_detector {

void FrameGaps::step(uint64_t seq, bool waited) {
  ++period_.received;
  if (last_seq_ && seq > *last_seq_ + 1) {
    const uint64_t missing = seq - *last_seq_ - 1;
    (waited ? lost_ : replaced_) += missing;
    if (waited) period_.lost += missing;
  }
  last_seq_ = seq;
}

FrameGapPeriod FrameGaps::take_period() {
  const FrameGapPeriod out = period_;
  period_ = {};
  return out;
}

bool frequent_losses(const FrameGapPeriod& period) {
  return period.lost >= 2 && period.lost * 10 >= period.received + period.lost;
}

}  // namespace stereoball::ball_detector
