#include "simulator/core/sim_params.hpp"

#include <cmath>
#include <sstream>

namespace stereoball::simulator {
namespace {

bool in_range(double v, double lo, double hi) {
  return std::isfinite(v) && v >= lo && v <= hi;
}

std::string range_error(const std::string& field, double v, double lo, double hi) {
  std::ostringstream s;
  s << field << " = " << v << " is out of range [" << lo << ", " << hi << "]";
  return s.str();
}

std::optional<std::string> check(const std::string& field, double v, double lo, double hi) {
  if (in_range(v, lo, hi)) return std::nullopt;
  return range_error(field, v, lo, hi);
}

std::optional<std::string> check_eye(const std::string& name, const EyeParams& e) {
  if (auto err = check(name + ".hfov_deg", e.hfov_deg, 20.0, 120.0)) return err;
  if (auto err = check(name + ".fy_over_fx", e.fy_over_fx, 0.8, 1.25)) return err;
  if (auto err = check(name + ".cx_offset_px", e.cx_offset_px, -50.0, 50.0)) return err;
  if (auto err = check(name + ".cy_offset_px", e.cy_offset_px, -50.0, 50.0)) return err;
  if (auto err = check(name + ".distortion[0] (k1)", e.distortion[0], -0.5, 0.5)) return err;
  if (auto err = check(name + ".distortion[1] (k2)", e.distortion[1], -0.5, 0.5)) return err;
  if (auto err = check(name + ".distortion[2] (p1)", e.distortion[2], -0.05, 0.05)) return err;
  if (auto err = check(name + ".distortion[3] (p2)", e.distortion[3], -0.05, 0.05)) return err;
  if (auto err = check(name + ".distortion[4] (k3)", e.distortion[4], -0.5, 0.5)) return err;
  return check(name + ".gain", e.gain, 0.1, 10.0);
}

std::optional<std::string> check_vec(const std::string& field, const Vec3d& v, double limit) {
  if (auto err = check(field + ".x", v.x, -limit, limit)) return err;
  if (auto err = check(field + ".y", v.y, -limit, limit)) return err;
  return check(field + ".z", v.z, -limit, limit);
}

}  // namespace

std::optional<std::string> SimParams::validate() const {
  if (width_px < 64 || width_px > 4096) return range_error("width_px", width_px, 64, 4096);
  if (height_px < 48 || height_px > 4096) return range_error("height_px", height_px, 48, 4096);
  if (auto err = check("frame_rate_hz", frame_rate_hz, 0.1, 1000.0)) return err;
  if (auto err = check_eye("left", left)) return err;
  if (auto err = check_eye("right", right)) return err;
  if (auto err = check("rig.baseline_m", rig.baseline_m, 0.01, 2.0)) return err;
  if (auto err = check("rig.height_m", rig.height_m, 0.05, 3.0)) return err;
  if (auto err = check("rig.forward_m", rig.forward_m, -1.0, 1.0)) return err;
  if (auto err = check("rig.tilt_rad", rig.tilt_rad, -1.0, 1.2)) return err;
  if (auto err = check_vec("rig.right_rotation_error_rad", rig.right_rotation_error_rad, 0.1))
    return err;
  if (auto err = check_vec("rig.right_offset_error_m", rig.right_offset_error_m, 0.05)) return err;
  if (auto err = check("rig.rectify_alpha", rig.rectify_alpha, -1.0, 1.0)) return err;
  if (auto err = check("robot.max_linear_mps", robot.max_linear_mps, 0.0, 10.0)) return err;
  if (auto err = check("robot.max_angular_radps", robot.max_angular_radps, 0.0, 20.0)) return err;
  if (auto err = check("robot.max_linear_accel_mps2", robot.max_linear_accel_mps2, 0.01, 100.0))
    return err;
  if (auto err =
          check("robot.max_angular_accel_radps2", robot.max_angular_accel_radps2, 0.01, 200.0))
    return err;
  if (auto err = check("robot.max_linear_brake_mps2", robot.max_linear_brake_mps2, 0.01, 100.0))
    return err;
  if (auto err =
          check("robot.max_angular_brake_radps2", robot.max_angular_brake_radps2, 0.01, 400.0))
    return err;
  if (robot.command_timeout_ns <= 0 || robot.command_timeout_ns > 60'000'000'000) {
    return range_error("robot.command_timeout_ns", static_cast<double>(robot.command_timeout_ns), 1,
                       60e9);
  }
  if (auto err = check("robot.radius_m", robot.radius_m, 0.0, 2.0)) return err;
  if (auto err = check("ball.rolling_decel_mps2", ball.rolling_decel_mps2, 0.0, 10.0)) return err;
  if (auto err = check("ball.restitution", ball.restitution, 0.0, 1.0)) return err;
  if (auto err = check("ball.physics_step_s", ball.physics_step_s, 1e-4, 0.05)) return err;
  if (auto err = check("sensor.noise_sigma_dn", sensor.noise_sigma_dn, 0.0, 50.0)) return err;
  if (sensor.motion_blur_subframes < 1 || sensor.motion_blur_subframes > 16) {
    return range_error("sensor.motion_blur_subframes", sensor.motion_blur_subframes, 1, 16);
  }
  return check("sensor.shutter_s", sensor.shutter_s, 0.0, 1.0 / frame_rate_hz);
}

}  // namespace stereoball::simulator
