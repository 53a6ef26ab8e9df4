#pragma once
// Gaps in the stereo/frame sequence numbers a detector receives, told apart by what the
// detector was doing (pure: the node says whether it was waiting). The reader keeps one frame:
// frames that arrive while a frame is being processed replace each other, and the newest is
// handed over as soon as the detector is free. So a frame that is handed over after the
// detector had been idle ends a gap whose frames never arrived (lost in transport: too large
// for the receive buffer, or a lossy link); a gap ending in a frame that was already waiting
// is counted as replaced while busy (a transport loss then is not told apart).

#include <cstdint>
#include <optional>

namespace stereoball::ball_detector {

/// Frames received and lost in one period (FrameGaps::take_period).
struct FrameGapPeriod {
  uint64_t received = 0;
  uint64_t lost = 0;  ///< never received (gaps that ended while the detector waited)
};

/// Counts the gaps of one frame source; a seq that goes backwards (the source restarted)
/// starts over without counting.
class FrameGaps {
 public:
  /// One received frame: its seq, and whether the detector was idle when it arrived.
  void step(uint64_t seq, bool waited);
  /// Frames never received, since construction.
  uint64_t lost() const { return lost_; }
  /// Frames missing from gaps that ended in a frame already waiting (the detector was busy).
  uint64_t replaced_while_busy() const { return replaced_; }
  /// The frames received and lost since the previous call.
  FrameGapPeriod take_period();

 private:
  std::optional<uint64_t> last_seq_;
  uint64_t lost_ = 0;
  uint64_t replaced_ = 0;
  FrameGapPeriod period_;
};

/// Whether a period's losses are frequent enough to warn: at least 2 frames and at least a
/// tenth of the frames published in the period.
bool frequent_losses(const FrameGapPeriod& period);

}  // namespace stereoball::ball_detector
