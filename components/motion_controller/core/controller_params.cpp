#include "motion_controller/core/controller_params.hpp"

#include <sstream>

namespace stereoball::motion_controller {
namespace {

template <typename T>
std::optional<std::string> check_range(const char* name, T value, T lo, T hi, const char* unit) {
  if (!(value >= lo && value <= hi)) {  // written so NaN fails too
    std::ostringstream os;
    os << name << " = " << value << " is out of range [" << lo << ", " << hi << "]" << unit;
    return os.str();
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> MotionControllerParams::validate() const {
  constexpr std::int64_t kHour = 3'600'000'000'000;
  for (const auto& r : {
           check_range("camera_right_offset_m", camera_right_offset_m, -2.0, 2.0, " m"),
           check_range("camera_forward_offset_m", camera_forward_offset_m, -2.0, 2.0, " m"),
           check_range("target_distance_m", target_distance_m, 0.1, 20.0, " m"),
           check_range("distance_gain_per_s", distance_gain_per_s, 0.0, 20.0, " 1/s"),
           check_range("bearing_gain_per_s", bearing_gain_per_s, 0.0, 50.0, " 1/s"),
           check_range("bearing_rate_feedforward", bearing_rate_feedforward, 0.0, 1.5, ""),
           check_range("distance_rate_feedforward", distance_rate_feedforward, 0.0, 1.5, ""),
           check_range("distance_deadband_m", distance_deadband_m, 0.0, 1.0, " m"),
           check_range("bearing_deadband_rad", bearing_deadband_rad, 0.0, 0.5, " rad"),
           check_range("slowdown_bearing_rad", slowdown_bearing_rad, 0.01, 3.2, " rad"),
           check_range("max_linear_mps", max_linear_mps, 0.0, 10.0, " m/s"),
           check_range("max_reverse_mps", max_reverse_mps, 0.0, 10.0, " m/s"),
           check_range("max_angular_radps", max_angular_radps, 0.0, 20.0, " rad/s"),
           check_range("max_linear_accel_mps2", max_linear_accel_mps2, 0.001, 100.0, " m/s^2"),
           check_range("max_angular_accel_radps2", max_angular_accel_radps2, 0.001, 500.0,
                       " rad/s^2"),
           check_range("max_linear_jerk_mps3", max_linear_jerk_mps3, 0.001, 10'000.0, " m/s^3"),
           check_range("max_angular_jerk_radps3", max_angular_jerk_radps3, 0.001, 10'000.0,
                       " rad/s^3"),
           check_range("search_angular_radps", search_angular_radps, 0.0, max_angular_radps,
                       " rad/s (at most max_angular_radps)"),
           check_range<std::int64_t>("search_timeout_ns", search_timeout_ns, 0, kHour, " ns"),
           check_range<std::int64_t>("stale_timeout_ns", stale_timeout_ns, 1'000'000, kHour, " ns"),
           check_range<std::int64_t>("position_hold_ns", position_hold_ns, 1, kHour, " ns"),
           check_range<std::int64_t>("max_step_ns", max_step_ns, 1'000'000, 10'000'000'000, " ns"),
           check_range<std::int64_t>("track_velocity_window_ns", track_velocity_window_ns, 0,
                                     10'000'000'000, " ns"),
           check_range<std::int64_t>("future_stamp_tolerance_ns", future_stamp_tolerance_ns, 0,
                                     10'000'000'000, " ns"),
       }) {
    if (r) return r;
  }
  return std::nullopt;
}

}  // namespace stereoball::motion_controller
