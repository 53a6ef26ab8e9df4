#include "motion_controller/core/motion_controller.hpp"

#include <algorithm>
#include <cmath>

namespace stereoball::motion_controller {
namespace {

double deadband(double value, double band) {
  return std::abs(value) < band ? 0.0 : value;
}

}  // namespace

MotionController::MotionController(const MotionControllerParams& params)
    : params_(params),
      linear_({params.max_linear_mps, -params.max_reverse_mps, params.max_linear_accel_mps2,
               params.max_linear_jerk_mps3}),
      angular_({params.max_angular_radps, -params.max_angular_radps,
                params.max_angular_accel_radps2, params.max_angular_jerk_radps3}) {}

void MotionController::on_track(const TrackSample& sample, std::int64_t now_ns) {
  const bool was_searching = track_ && track_->state == TrackState::kSearching;
  if (sample.state == TrackState::kSearching && !was_searching) search_started_ns_ = now_ns;
  track_ = sample;
  track_received_ns_ = now_ns;
}

void MotionController::on_estop(bool engaged) {
  estop_ = engaged;
}

Command MotionController::step(std::int64_t now_ns) {
  const std::int64_t dt_ns =
      last_step_ns_ ? std::clamp<std::int64_t>(now_ns - *last_step_ns_, 0, params_.max_step_ns) : 0;
  last_step_ns_ = now_ns;
  // Safety stops are immediate, not ramped: the base must not keep moving.
  if (estop_) return hard_stop(Mode::kEmergencyStop);
  if (!track_) return hard_stop(Mode::kWaiting);
  if (now_ns - track_received_ns_ > params_.stale_timeout_ns) return hard_stop(Mode::kStale);

  Target target;
  switch (track_->state) {
    case TrackState::kIdle:
      target.mode = Mode::kIdle;
      break;
    case TrackState::kFollowing:
      target = following_target(*track_);
      break;
    case TrackState::kSearching:
      target = searching_target(now_ns);
      break;
  }
  const double dt_s = static_cast<double>(dt_ns) * 1e-9;
  Command c;
  c.linear_mps = linear_.step(target.linear_mps, dt_s);
  c.angular_radps = angular_.step(target.angular_radps, dt_s);
  c.mode = target.mode;
  return c;
}

MotionController::Target MotionController::following_target(const TrackSample& t) const {
  Target out;
  const bool fresh = t.capture_stamp_ns - t.last_accepted_stamp_ns <= params_.position_hold_ns;
  if (!t.position_valid || !fresh) {
    out.mode = Mode::kHolding;  // steering on an old position would overshoot
    return out;
  }
  out.mode = Mode::kFollowing;
  // Steer the robot's centreline, not the left camera's optical axis, at the ball.
  const double right_m = t.distance_m * std::sin(t.bearing_rad) + params_.camera_right_offset_m;
  const double forward_m = t.distance_m * std::cos(t.bearing_rad) + params_.camera_forward_offset_m;
  const double bearing_rad = std::atan2(right_m, forward_m);
  const double distance_m = std::hypot(right_m, forward_m);
  // Camera x points right: a ball to the right (positive bearing) needs a
  // clockwise (negative) turn.
  // The camera sees the ball's own bearing rate plus the robot's turn (turning
  // left moves the ball right); the difference is what the robot must match.
  const double ball_rate_radps = t.bearing_rate_radps - angular_.velocity();
  out.angular_radps =
      -params_.bearing_gain_per_s * deadband(bearing_rad, params_.bearing_deadband_rad) -
      params_.bearing_rate_feedforward * ball_rate_radps;
  const double distance_error =
      deadband(distance_m - params_.target_distance_m, params_.distance_deadband_m);
  // Turn first, then drive: off-centre balls get less forward speed.
  const double centred =
      std::clamp(1.0 - std::abs(bearing_rad) / params_.slowdown_bearing_rad, 0.0, 1.0);
  // Driving forward shortens the range: the ball's own range rate is the sum.
  const double ball_range_rate_mps = t.distance_rate_mps + linear_.velocity();
  out.linear_mps =
      params_.distance_gain_per_s * distance_error * (distance_error > 0 ? centred : 1.0) +
      params_.distance_rate_feedforward * ball_range_rate_mps * centred;
  return out;
}

MotionController::Target MotionController::searching_target(std::int64_t now_ns) const {
  Target out;
  if (now_ns - search_started_ns_ > params_.search_timeout_ns) {
    out.mode = Mode::kSearchGaveUp;
    return out;
  }
  out.mode = Mode::kSearching;
  bool left = params_.search_left_when_unknown;
  if (track_->last_seen_side == Side::kLeft) left = true;
  if (track_->last_seen_side == Side::kRight) left = false;
  out.angular_radps = left ? params_.search_angular_radps : -params_.search_angular_radps;
  return out;
}

Command MotionController::hard_stop(Mode mode) {
  linear_.reset();
  angular_.reset();
  Command c;
  c.mode = mode;
  return c;
}

}  // namespace stereoball::motion_controller
