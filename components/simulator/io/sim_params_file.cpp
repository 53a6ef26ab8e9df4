#include "simulator/io/sim_params_file.hpp"

#include <vector>

namespace stereoball::simulator {
namespace {

void read_eye(params::ParamsFile& f, const std::string& name, EyeParams& e) {
  f.read(name + ".hfov_deg", e.hfov_deg, 20.0, 120.0);
  f.read(name + ".fy_over_fx", e.fy_over_fx, 0.8, 1.25);
  f.read(name + ".cx_offset_px", e.cx_offset_px, -50.0, 50.0);
  f.read(name + ".cy_offset_px", e.cy_offset_px, -50.0, 50.0);
  std::vector<double> d(e.distortion.begin(), e.distortion.end());
  f.read(name + ".distortion", d, 5);
  if (d.size() == 5) std::copy(d.begin(), d.end(), e.distortion.begin());
  f.read(name + ".gain", e.gain, 0.1, 10.0);
}

void read_vec3(params::ParamsFile& f, const std::string& key, Vec3d& v) {
  std::vector<double> d{v.x, v.y, v.z};
  f.read(key, d, 3);
  if (d.size() == 3) v = {d[0], d[1], d[2]};
}

}  // namespace

void read_sim_params(params::ParamsFile& f, SimParams& p) {
  f.read("width_px", p.width_px, 64, 4096);
  f.read("height_px", p.height_px, 48, 4096);
  f.read("frame_rate_hz", p.frame_rate_hz, 0.1, 1000.0);
  read_eye(f, "left", p.left);
  read_eye(f, "right", p.right);
  f.read("rig.baseline_m", p.rig.baseline_m, 0.01, 2.0);
  f.read("rig.height_m", p.rig.height_m, 0.05, 3.0);
  f.read("rig.forward_m", p.rig.forward_m, -1.0, 1.0);
  f.read("rig.tilt_rad", p.rig.tilt_rad, -1.0, 1.2);
  read_vec3(f, "rig.right_rotation_error_rad", p.rig.right_rotation_error_rad);
  read_vec3(f, "rig.right_offset_error_m", p.rig.right_offset_error_m);
  f.read("rig.rectify_alpha", p.rig.rectify_alpha, -1.0, 1.0);
  f.read("robot.max_linear_mps", p.robot.max_linear_mps, 0.0, 10.0);
  f.read("robot.max_angular_radps", p.robot.max_angular_radps, 0.0, 20.0);
  f.read("robot.max_linear_accel_mps2", p.robot.max_linear_accel_mps2, 0.01, 100.0);
  f.read("robot.max_angular_accel_radps2", p.robot.max_angular_accel_radps2, 0.01, 200.0);
  f.read("robot.max_linear_brake_mps2", p.robot.max_linear_brake_mps2, 0.01, 100.0);
  f.read("robot.max_angular_brake_radps2", p.robot.max_angular_brake_radps2, 0.01, 400.0);
  f.read("robot.command_timeout_ns", p.robot.command_timeout_ns, int64_t{1},
         int64_t{60'000'000'000});
  f.read("robot.radius_m", p.robot.radius_m, 0.0, 2.0);
  f.read("ball.rolling_decel_mps2", p.ball.rolling_decel_mps2, 0.0, 10.0);
  f.read("ball.restitution", p.ball.restitution, 0.0, 1.0);
  f.read("ball.physics_step_s", p.ball.physics_step_s, 1e-4, 0.05);
  f.read("sensor.noise_sigma_dn", p.sensor.noise_sigma_dn, 0.0, 50.0);
  f.read("sensor.motion_blur_subframes", p.sensor.motion_blur_subframes, 1, 16);
  f.read("sensor.shutter_s", p.sensor.shutter_s, 0.0, 1.0);
}

Result<SimulatorConfig> load_simulator_config(const std::string& path) {
  auto file = params::ParamsFile::load(path);
  if (!file) return Error{file.error()};
  SimulatorConfig c;
  read_sim_params(*file, c.sim);
  file->read_choice("frame_encoding", c.output.frame_encoding,
                    camera_server::frame_encoding_choices());
  file->read("jpeg_quality", c.output.jpeg_quality, 1, 100);
  if (auto e = c.sim.validate()) file->fail(*e);
  if (auto e = c.output.validate()) file->fail(*e);
  if (auto e = file->finish()) return Error{*e};
  return c;
}

Result<SimParams> load_sim_params(const std::string& path) {
  auto c = load_simulator_config(path);
  if (!c) return Error{c.error()};
  return c->sim;
}

}  // namespace stereoball::simulator
