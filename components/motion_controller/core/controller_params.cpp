#include "motion_controller/core/controller_params.hpp"

namespace stereoball::motion_controller {
namespace {

using params::at;
using params::number;
using P = MotionControllerParams;
constexpr std::int64_t kHour = 3'600'000'000'000;
constexpr std::int64_t k10s = 10'000'000'000;

// Searching may not turn faster than the robot is allowed to.
Status search_within_limit(const P& p) {
  if (p.search_angular_radps <= p.max_angular_radps) return {};
  return Error{params::out_of_range("search_angular_radps", p.search_angular_radps,
                                    {0.0, p.max_angular_radps}, "rad/s",
                                    "at most max_angular_radps")};
}

params::FieldTable<P> make_table() {
  return {
      {
          number("camera_right_offset_m", at(&P::camera_right_offset_m), -0.06, {-2.0, 2.0}, "m",
                 "left camera right of the robot centreline (sim rig: -baseline/2)"),
          number("camera_forward_offset_m", at(&P::camera_forward_offset_m), 0.10, {-2.0, 2.0}, "m",
                 "left camera ahead of the robot centre"),
          number("target_distance_m", at(&P::target_distance_m), 1.0, {0.1, 20.0}, "m",
                 "distance robot centre -> ball to keep"),
          number("distance_gain_per_s", at(&P::distance_gain_per_s), 1.0, {0.0, 20.0}, "1/s",
                 "linear = gain * (distance - target)"),
          number("bearing_gain_per_s", at(&P::bearing_gain_per_s), 4.0, {0.0, 50.0}, "1/s",
                 "angular = -gain * bearing"),
          number("bearing_rate_feedforward", at(&P::bearing_rate_feedforward), 0.6, {0.0, 1.5}, "",
                 "fraction of the ball's bearing rate fed forward"),
          number("distance_rate_feedforward", at(&P::distance_rate_feedforward), 1.0, {0.0, 1.5},
                 "", "fraction of the ball's range rate fed forward"),
          number("distance_deadband_m", at(&P::distance_deadband_m), 0.02, {0.0, 1.0}, "m",
                 "distance errors below this are ignored"),
          number("bearing_deadband_rad", at(&P::bearing_deadband_rad), 0.005, {0.0, 0.5}, "rad",
                 "bearing errors below this are ignored"),
          number("slowdown_bearing_rad", at(&P::slowdown_bearing_rad), 0.6, {0.01, 3.2}, "rad",
                 "forward speed scales with 1 - abs(bearing) / this"),
          number("max_linear_mps", at(&P::max_linear_mps), 0.8, {0.0, 10.0}, "m/s",
                 "max forward speed"),
          number("max_reverse_mps", at(&P::max_reverse_mps), 0.2, {0.0, 10.0}, "m/s",
                 "max backward speed"),
          number("max_angular_radps", at(&P::max_angular_radps), 1.5, {0.0, 20.0}, "rad/s",
                 "max yaw rate"),
          number("max_linear_accel_mps2", at(&P::max_linear_accel_mps2), 0.8, {0.001, 100.0},
                 "m/s^2", "max linear acceleration"),
          number("max_linear_brake_mps2", at(&P::max_linear_brake_mps2), 2.0, {0.001, 100.0},
                 "m/s^2", "max linear deceleration (speed magnitude dropping)"),
          number("max_angular_accel_radps2", at(&P::max_angular_accel_radps2), 4.0, {0.001, 500.0},
                 "rad/s^2", "max angular acceleration"),
          number("max_linear_jerk_mps3", at(&P::max_linear_jerk_mps3), 4.0, {0.001, 10'000.0},
                 "m/s^3", "max linear jerk"),
          number("max_angular_jerk_radps3", at(&P::max_angular_jerk_radps3), 30.0,
                 {0.001, 10'000.0}, "rad/s^3", "max angular jerk"),
          number("search_angular_radps", at(&P::search_angular_radps), 0.8, {0.0, 20.0}, "rad/s",
                 "rotation speed while searching (at most max_angular_radps)"),
          number("search_timeout_ns", at(&P::search_timeout_ns), 20'000'000'000, {0, kHour}, "ns",
                 "give up searching and stop after this long"),
          params::flag("search_left_when_unknown", at(&P::search_left_when_unknown), true,
                       "search direction when the last-seen side is unknown"),
          number("stale_timeout_ns", at(&P::stale_timeout_ns), 300'000'000, {1'000'000, kHour},
                 "ns", "no ball/track for this long -> zero command"),
          number("position_hold_ns", at(&P::position_hold_ns), 300'000'000, {1, kHour}, "ns",
                 "following on a position older than this -> slow to a stop"),
          number("max_step_ns", at(&P::max_step_ns), 200'000'000, {1'000'000, k10s}, "ns",
                 "longest control period integrated at once"),
          number("track_velocity_window_ns", at(&P::track_velocity_window_ns), 500'000'000,
                 {0, k10s}, "ns", "the tracker's velocity_window_ns: own motion averaged over it"),
          number("future_stamp_tolerance_ns", at(&P::future_stamp_tolerance_ns), 100'000'000,
                 {0, k10s}, "ns", "a track's capture stamp may lead our clock by this much"),
      },
      search_within_limit};
}

}  // namespace

SB_PARAMS_TABLE(MotionControllerParams, controller_fields, make_table)

}  // namespace stereoball::motion_controller
