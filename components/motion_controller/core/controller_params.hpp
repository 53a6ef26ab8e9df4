#pragma once
// Parameters of the motion controller core: following law, limits, search.

#include <cstdint>
#include <optional>
#include <string>

namespace stereoball::motion_controller {

/// Controller configuration; units are in the field names.
struct MotionControllerParams {
  /// Where the left camera (origin of ball/track) sits right of the robot's centreline, m
  /// (negative = left; the simulated rig: -baseline/2 = -0.06).
  double camera_right_offset_m = -0.06;
  /// Where the left camera sits ahead of the robot's centre, metres.
  double camera_forward_offset_m = 0.10;
  /// Distance to keep between the robot's centre and the ball, metres.
  double target_distance_m = 1.0;
  /// linear = gain * (distance - target), 1/s.
  double distance_gain_per_s = 1.0;
  /// angular = -gain * bearing, 1/s (ball to the right -> turn right = negative).
  double bearing_gain_per_s = 4.0;
  /// Fraction of the ball's own bearing rate fed forward (0 = pure P control), unitless.
  double bearing_rate_feedforward = 0.6;
  /// Fraction of the ball's own range rate fed forward (0 = pure P control), unitless.
  double distance_rate_feedforward = 0.6;
  /// Distance errors smaller than this give no linear command, metres.
  double distance_deadband_m = 0.02;
  /// Bearing errors smaller than this give no angular command, radians.
  double bearing_deadband_rad = 0.005;
  /// Forward speed scales with 1 - |bearing| / this (turn first, then drive), radians.
  double slowdown_bearing_rad = 0.6;
  /// Max forward speed, m/s.
  double max_linear_mps = 0.8;
  /// Max backward speed (positive number), m/s.
  double max_reverse_mps = 0.2;
  /// Max yaw rate, rad/s.
  double max_angular_radps = 1.5;
  /// Max linear acceleration, m/s^2.
  double max_linear_accel_mps2 = 0.8;
  /// Max angular acceleration, rad/s^2.
  double max_angular_accel_radps2 = 4.0;
  /// Max linear jerk, m/s^3.
  double max_linear_jerk_mps3 = 4.0;
  /// Max angular jerk, rad/s^3.
  double max_angular_jerk_radps3 = 30.0;
  /// Rotation speed while searching (magnitude), rad/s.
  double search_angular_radps = 0.8;
  /// Searching stops (zero command) after this long, ns.
  std::int64_t search_timeout_ns = 20'000'000'000;
  /// Rotate left when the last-seen side is unknown (else right).
  bool search_left_when_unknown = true;
  /// No ball/track sample for this long -> zero command, ns.
  std::int64_t stale_timeout_ns = 300'000'000;
  /// Following, but the last accepted position is older than this -> slow to a stop, ns.
  std::int64_t position_hold_ns = 300'000'000;
  /// Longest control period used for integration; longer gaps are clamped, ns.
  std::int64_t max_step_ns = 200'000'000;
  /// Span of the tracker's velocity fit (its velocity_window_ns), ns: the track's bearing and
  /// range rates average the robot's own motion over this span before the last accepted
  /// position, so that same average (not the present velocity) is removed from them.
  std::int64_t track_velocity_window_ns = 500'000'000;
  /// A track's capture stamp may lead the receiver's clock by this much (clock offset between
  /// hosts); a later stamp is rejected as lying in the future, ns.
  std::int64_t future_stamp_tolerance_ns = 100'000'000;

  /// Empty when valid; otherwise names the bad field and its allowed range.
  std::optional<std::string> validate() const;
};

}  // namespace stereoball::motion_controller
