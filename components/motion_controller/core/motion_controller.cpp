#include "motion_controller/core/motion_controller.hpp"

#include <algorithm>
#include <cmath>

namespace stereoball::motion_controller {
namespace {

double deadband(double value, double band) {
  return std::abs(value) < band ? 0.0 : value;
}

// The track's position in the left camera's floor plane (x right, z forward), metres.
PlaneVector camera_position_m(const TrackSample& t) {
  return {t.distance_m * std::sin(t.bearing_rad), t.distance_m * std::cos(t.bearing_rad)};
}

}  // namespace

MotionController::MotionController(const MotionControllerParams& params)
    : params_(params),
      linear_({params.max_linear_mps, -params.max_reverse_mps, params.max_linear_accel_mps2,
               params.max_linear_jerk_mps3, params.max_linear_brake_mps2}),
      angular_({params.max_angular_radps, -params.max_angular_radps,
                params.max_angular_accel_radps2, params.max_angular_jerk_radps3,
                params.max_angular_accel_radps2}) {}

StampCheck MotionController::check_stamp(std::int64_t capture_stamp_ns, std::int64_t now_ns) const {
  if (capture_stamp_ns <= 0) return StampCheck::kZero;
  if (capture_stamp_ns > now_ns + params_.future_stamp_tolerance_ns) return StampCheck::kFuture;
  if (!track_) return StampCheck::kNew;
  if (capture_stamp_ns == track_->capture_stamp_ns) return StampCheck::kRepeated;
  // After the input went stale the old stream is over (a source restarted, a clock was set):
  // a new stream may start earlier. While it is live, an earlier frame would steer backwards.
  if (capture_stamp_ns < track_->capture_stamp_ns && !input_stale(now_ns)) {
    return StampCheck::kBackwards;
  }
  return StampCheck::kNew;
}

MotionController::TrackResponse MotionController::on_track(const TrackSample& sample,
                                                           std::int64_t now_ns) {
  TrackResponse response;
  response.check = check_stamp(sample.capture_stamp_ns, now_ns);
  if (response.check != StampCheck::kNew) return response;
  store(sample, now_ns);
  Command c = step(now_ns);
  c.capture_stamp_ns = sample.capture_stamp_ns;
  response.command = c;
  return response;
}

void MotionController::store(const TrackSample& sample, std::int64_t now_ns) {
  const bool was_searching = track_ && track_->state == TrackState::kSearching;
  if (sample.state == TrackState::kSearching && !was_searching) {
    search_started_ns_ = now_ns;
    // Chosen once: the direction must not flip while the robot turns.
    search_left_ = search_left(sample, now_ns);
  }
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
  if (estop_) return record(hard_stop(Mode::kEmergencyStop), now_ns);
  if (!track_) return record(hard_stop(Mode::kWaiting), now_ns);
  if (input_stale(now_ns)) return record(hard_stop(Mode::kStale), now_ns);

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
  return record(c, now_ns);
}

Command MotionController::record(const Command& c, std::int64_t now_ns) {
  history_.record(now_ns, {c.linear_mps, c.angular_radps});
  // Enough history for the oldest velocity window a usable track can refer to.
  const std::int64_t keep_ns = params_.track_velocity_window_ns + params_.position_hold_ns +
                               params_.stale_timeout_ns + params_.max_step_ns;
  history_.forget_before(now_ns - keep_ns);
  return c;
}

Velocity MotionController::own_motion_behind(const TrackSample& t, std::int64_t received_ns) const {
  if (params_.track_velocity_window_ns <= 0) return {linear_.velocity(), angular_.velocity()};
  // The fit ends at the last accepted capture: its age in the sender's clock, moved to ours.
  const std::int64_t end_ns =
      received_ns - std::max<std::int64_t>(0, t.capture_stamp_ns - t.last_accepted_stamp_ns);
  return history_.slope_weighted_mean(end_ns - params_.track_velocity_window_ns, end_ns);
}

PlaneVector MotionController::from_robot_centre(const PlaneVector& camera_m) const {
  return {camera_m.x + params_.camera_right_offset_m, camera_m.z + params_.camera_forward_offset_m};
}

bool MotionController::search_left(const TrackSample& t, std::int64_t now_ns) const {
  bool left = params_.search_left_when_unknown;
  if (t.last_seen_side == Side::kLeft) left = true;
  if (t.last_seen_side == Side::kRight) left = false;
  constexpr double kMinDistanceM = 0.05;  // closer is no usable position
  if (!t.position_valid || t.distance_m < kMinDistanceM) return left;
  // Where the ball is now as seen from the robot's centre (the tracker's side is the left
  // camera's image side: a close ball right of the camera axis can be left of the robot).
  const std::int64_t age_ns =
      std::max<std::int64_t>(0, t.capture_stamp_ns - t.last_accepted_stamp_ns);
  LostBall ball;
  const PlaneVector camera_m = camera_position_m(t);
  ball.last_m = from_robot_centre(camera_m);
  ball.seen_velocity_mps = plane_velocity(camera_m, {t.bearing_rate_radps, t.distance_rate_mps});
  ball.own_while_seen = own_motion_behind(t, now_ns);
  ball.age_s = static_cast<double>(age_ns) * 1e-9;
  ball.own_since = history_.mean(now_ns - age_ns, now_ns);
  const PlaneVector now_m = predict_lost_ball(ball);
  const double predicted = std::atan2(now_m.x, now_m.z);
  if (std::abs(predicted) < params_.bearing_deadband_rad) return left;  // too close to call
  return predicted < 0.0;                                               // positive bearing = right
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
  const PlaneVector ball_m = from_robot_centre(camera_position_m(t));
  const double bearing_rad = std::atan2(ball_m.x, ball_m.z);
  const double distance_m = std::hypot(ball_m.x, ball_m.z);
  // Camera x points right: a ball to the right (positive bearing) needs a
  // clockwise (negative) turn.
  // The camera sees the ball's own bearing rate plus the robot's turn (turning
  // left moves the ball right); the difference is what the robot must match. The seen rate
  // is a fit over a past window, so the robot's turn over that window is removed, not the
  // present one (which made the loop oscillate: a phantom ball motion that grows).
  const Velocity own = own_motion_behind(t, track_received_ns_);
  const double ball_rate_radps = t.bearing_rate_radps - own.angular_radps;
  out.angular_radps =
      -params_.bearing_gain_per_s * deadband(bearing_rad, params_.bearing_deadband_rad) -
      params_.bearing_rate_feedforward * ball_rate_radps;
  const double distance_error =
      deadband(distance_m - params_.target_distance_m, params_.distance_deadband_m);
  // Turn first, then drive: off-centre balls get less forward speed.
  const double centred =
      std::clamp(1.0 - std::abs(bearing_rad) / params_.slowdown_bearing_rad, 0.0, 1.0);
  // Driving forward shortens the range: the ball's own range rate is the sum.
  const double ball_range_rate_mps = t.distance_rate_mps + own.linear_mps;
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
  out.angular_radps = search_left_ ? params_.search_angular_radps : -params_.search_angular_radps;
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
