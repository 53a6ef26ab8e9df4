#pragma once
// The motion controller: follows the ball (centre it, keep the target
// distance), searches toward the side it was last seen, and stops on start-up,
// stale input and emergency stop. Event-driven: each new track is answered at once; a
// timer only keeps a minimum rate. Pure: time is an argument.

#include <cstdint>
#include <optional>

#include "motion_controller/core/controller_params.hpp"
#include "motion_controller/core/lost_ball.hpp"
#include "motion_controller/core/own_motion.hpp"
#include "motion_controller/core/smooth_axis.hpp"
#include "motion_controller/core/types.hpp"

namespace stereoball::motion_controller {

/// Turns the latest track into smooth, limited velocity commands.
class MotionController {
 public:
  /// params must be valid (MotionControllerParams::validate() succeeded).
  explicit MotionController(const MotionControllerParams& params);

  /// What a track sample received at now_ns (receiver clock, ns) led to.
  struct TrackResponse {
    StampCheck check = StampCheck::kNew;
    /// The command answering the sample (its capture_stamp_ns set); only for StampCheck::kNew.
    std::optional<Command> command;
  };
  /// Checks the sample's capture stamp; a new one is stored and answered at once with the
  /// command for now_ns. A sample with a bad or repeated stamp changes nothing.
  TrackResponse on_track(const TrackSample& sample, std::int64_t now_ns);
  /// Engages (latches) or clears the emergency stop.
  void on_estop(bool engaged);
  /// The command at now_ns (receiver clock, ns) without a new track: minimum-rate timer,
  /// stale input, emergency stop. Its capture_stamp_ns is 0.
  Command step(std::int64_t now_ns);
  /// True when a timer that checks every check_period_ns must command at now_ns so that no two
  /// commands lie more than period_ns apart (also before the first command).
  bool minimum_rate_due(std::int64_t now_ns, std::int64_t period_ns,
                        std::int64_t check_period_ns) const {
    return !last_step_ns_ || now_ns - *last_step_ns_ >= period_ns - check_period_ns;
  }

  /// When (receiver clock, ns) the input goes stale: the first instant input_stale() holds,
  /// none before the first track. A timer set for it sends the stale stop without polling.
  std::optional<std::int64_t> stale_at_ns() const {
    if (!track_) return std::nullopt;
    return track_received_ns_ + params_.stale_timeout_ns + 1;
  }
  /// Receiver-clock time of the last command (step()), none before the first.
  std::optional<std::int64_t> last_command_ns() const { return last_step_ns_; }

  /// True while the emergency stop is latched.
  bool estop_engaged() const { return estop_; }
  /// True when a track was received once but none for longer than stale_timeout_ns (the next
  /// step() commands the immediate zero of the stale mode).
  bool input_stale(std::int64_t now_ns) const {
    return track_.has_value() && now_ns - track_received_ns_ > params_.stale_timeout_ns;
  }

 private:
  struct Target {
    double linear_mps = 0.0;
    double angular_radps = 0.0;
    Mode mode = Mode::kIdle;
  };

  StampCheck check_stamp(std::int64_t capture_stamp_ns, std::int64_t now_ns) const;
  void store(const TrackSample& sample, std::int64_t now_ns);
  Target following_target(const TrackSample& t) const;
  Target searching_target(std::int64_t now_ns) const;
  Command hard_stop(Mode mode);
  Command record(const Command& c, std::int64_t now_ns);
  Velocity own_motion_behind(const TrackSample& t, std::int64_t received_ns) const;
  // A point of the left camera's floor plane as seen from the robot's centre (same axes).
  PlaneVector from_robot_centre(const PlaneVector& camera_m) const;
  bool search_left(const TrackSample& t, std::int64_t now_ns) const;

  MotionControllerParams params_;
  SmoothAxis linear_;
  SmoothAxis angular_;
  OwnMotionHistory history_;
  std::optional<TrackSample> track_;
  std::int64_t track_received_ns_ = 0;
  std::int64_t search_started_ns_ = 0;
  bool search_left_ = true;  // direction chosen when the search started
  std::optional<std::int64_t> last_step_ns_;
  bool estop_ = false;
};

}  // namespace stereoball::motion_controller
