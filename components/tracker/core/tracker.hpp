#pragma once
// The tracker of paper section IV: combines circle detections, block matching
// and statistical verification into a track with state idle / following /
// searching, and remembers on which side the ball was last seen.

#include <Eigen/Core>

#include <cstdint>
#include <deque>
#include <string>

#include "tracker/core/block_matcher.hpp"
#include "tracker/core/position_register.hpp"
#include "tracker/core/tracker_params.hpp"
#include "tracker/core/types.hpp"

namespace stereoball::tracker {

/// Decides per detection whether it is the ball, and keeps the track state.
class Tracker {
 public:
  /// params must be valid (TrackerParams::validate() succeeded).
  explicit Tracker(const TrackerParams& params);

  /// Processes one detection captured at now_ns (capture stamp, ns) and returns the track.
  Track step(const Detection& detection, std::int64_t now_ns);

  /// Current state.
  TrackState state() const { return state_; }
  /// The shift register of recent positions (for inspection and tests).
  const PositionRegister& position_register() const { return register_; }
  /// True once a reference block is stored.
  bool has_reference_block() const { return matcher_.has_reference(); }
  /// Back to the start-up state, forgetting everything.
  void reset();

 private:
  struct Decision {
    Verdict verdict = Verdict::kNoDetection;
    std::string reason;
    double ssd = -1.0;
  };

  bool in_range(const Eigen::Vector3d& position_m) const;
  std::string out_of_range_text(const Eigen::Vector3d& position_m) const;
  Decision decide_startup(const Detection& d, std::int64_t now_ns);
  Decision decide_tracking(const Detection& d, std::int64_t now_ns);
  void accept(const Detection& d, std::int64_t now_ns);
  void note_input(std::int64_t now_ns);
  void miss(std::int64_t now_ns);
  void update_velocity(std::int64_t now_ns);
  Side side_of(const Detection& d) const;
  Track make_track(const Decision& decision) const;

  TrackerParams params_;
  BlockMatcher matcher_;
  PositionRegister register_;
  TrackState state_ = TrackState::kIdle;
  std::deque<StampedPosition> accepted_;  // recent accepted positions, for the velocity fit
  bool has_accepted_ = false;
  Eigen::Vector3d last_position_m_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_mps_ = Eigen::Vector3d::Zero();
  std::int64_t last_accepted_ns_ = 0;
  Side side_ = Side::kUnknown;
  int frames_since_accept_ = 0;
  // Input gaps (a cut link, a stalled detector) are no evidence that the ball is lost: the
  // loss clock restarts at the first detection after a gap longer than lost_after_ns.
  bool has_input_ = false;
  std::int64_t last_input_ns_ = 0;
  std::int64_t loss_clock_from_ns_ = 0;
};

}  // namespace stereoball::tracker
