#include "motion_controller/node/controller_params_file.hpp"

namespace stereoball::motion_controller {

Result<MotionControllerNodeParams> read_controller_params(params::ParamsFile& file) {
  constexpr std::int64_t kHour = 3'600'000'000'000;
  MotionControllerNodeParams n;
  MotionControllerParams& p = n.controller;
  file.read("rate_hz", n.rate_hz, 1.0, 1000.0);
  file.read("camera_right_offset_m", p.camera_right_offset_m, -2.0, 2.0);
  file.read("camera_forward_offset_m", p.camera_forward_offset_m, -2.0, 2.0);
  file.read("target_distance_m", p.target_distance_m, 0.1, 20.0);
  file.read("distance_gain_per_s", p.distance_gain_per_s, 0.0, 20.0);
  file.read("bearing_gain_per_s", p.bearing_gain_per_s, 0.0, 50.0);
  file.read("bearing_rate_feedforward", p.bearing_rate_feedforward, 0.0, 1.5);
  file.read("distance_rate_feedforward", p.distance_rate_feedforward, 0.0, 1.5);
  file.read("distance_deadband_m", p.distance_deadband_m, 0.0, 1.0);
  file.read("bearing_deadband_rad", p.bearing_deadband_rad, 0.0, 0.5);
  file.read("slowdown_bearing_rad", p.slowdown_bearing_rad, 0.01, 3.2);
  file.read("max_linear_mps", p.max_linear_mps, 0.0, 10.0);
  file.read("max_reverse_mps", p.max_reverse_mps, 0.0, 10.0);
  file.read("max_angular_radps", p.max_angular_radps, 0.0, 20.0);
  file.read("max_linear_accel_mps2", p.max_linear_accel_mps2, 0.001, 100.0);
  file.read("max_angular_accel_radps2", p.max_angular_accel_radps2, 0.001, 500.0);
  file.read("max_linear_jerk_mps3", p.max_linear_jerk_mps3, 0.001, 10'000.0);
  file.read("max_angular_jerk_radps3", p.max_angular_jerk_radps3, 0.001, 10'000.0);
  file.read("search_angular_radps", p.search_angular_radps, 0.0, 20.0);
  file.read("search_timeout_ns", p.search_timeout_ns, std::int64_t{0}, kHour);
  file.read("search_left_when_unknown", p.search_left_when_unknown);
  file.read("stale_timeout_ns", p.stale_timeout_ns, std::int64_t{1'000'000}, kHour);
  file.read("position_hold_ns", p.position_hold_ns, std::int64_t{1}, kHour);
  file.read("max_step_ns", p.max_step_ns, std::int64_t{1'000'000}, std::int64_t{10'000'000'000});
  file.read("track_velocity_window_ns", p.track_velocity_window_ns, std::int64_t{0},
            std::int64_t{10'000'000'000});
  file.read("future_stamp_tolerance_ns", p.future_stamp_tolerance_ns, std::int64_t{0},
            std::int64_t{10'000'000'000});
  if (auto e = p.validate()) file.fail(file.name() + ": " + *e);
  if (auto e = file.finish()) return Error{*e};
  return n;
}

Result<MotionControllerNodeParams> load_controller_params(const std::string& path) {
  auto file = params::ParamsFile::load(path);
  if (!file) return Error{file.error()};
  return read_controller_params(*file);
}

}  // namespace stereoball::motion_controller
