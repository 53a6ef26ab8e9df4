#include "simulator/core/simulator.hpp"

#include <algorithm>
#include <cmath>

namespace stereoball::simulator {
namespace {

// The scenario may stand for a slower base than the configured one (never a faster one).
SimParams with_scenario_base(SimParams params, const Scenario& scenario) {
  if (scenario.robot_max_angular_radps)
    params.robot.max_angular_radps =
        std::min(params.robot.max_angular_radps, *scenario.robot_max_angular_radps);
  return params;
}

}  // namespace

Simulator::Simulator(const SimParams& params, const Scenario& scenario)
    : params_(params),
      scenario_(scenario),
      rig_(params),
      world_(with_scenario_base(params, scenario), scenario_),
      renderer_(rig_, scenario_, params.left.gain, params.right.gain),
      sensor_(params.sensor.noise_sigma_dn, scenario.seed),
      occluders_(solid_boxes(scenario)) {}

std::optional<std::string> Simulator::check(const SimParams& params, const Scenario& scenario) {
  if (auto st = params.validate(); !st) return "simulator params: " + st.error();
  if (auto e = scenario.validate()) return "scenario '" + scenario.name + "': " + *e;
  return std::nullopt;
}

int64_t Simulator::frame_period_ns() const {
  return static_cast<int64_t>(std::llround(1e9 / params_.frame_rate_hz));
}

void Simulator::advance(const std::optional<VelocityCommand>& command, int64_t sim_time_ns) {
  if (command) world_.set_command(*command);
  world_.advance_to(sim_time_ns);
}

SimFrame Simulator::step(const std::optional<VelocityCommand>& command, int64_t sim_time_ns) {
  if (command) world_.set_command(*command);
  SimFrame f;
  f.seq = seq_++;
  f.sim_time_ns = std::max(sim_time_ns, world_.time_ns());
  render_eye(Eye::kLeft, f.sim_time_ns, f.left);
  render_eye(Eye::kRight, f.sim_time_ns, f.right);
  world_.advance_to(f.sim_time_ns);
  sensor_.apply(f.left);
  sensor_.apply(f.right);
  f.truth =
      make_ground_truth(rig_, world_.robot(), world_.ball(), f.seq, f.sim_time_ns, occluders_);
  return f;
}

void Simulator::render_eye(Eye eye, int64_t t_ns, cv::Mat& out) {
  const int n = params_.sensor.motion_blur_subframes;
  if (n <= 1) {
    world_.advance_to(t_ns);
    const LightKey light = lighting_at(scenario_, world_.time_ns() * 1e-9);
    renderer_.render(eye, world_.robot(), world_.ball(), light, out);
    return;
  }
  // Motion blur: average n renders spread over the shutter interval ending at t_ns. The world
  // only moves forward, so both eyes see the same sub-times only if the left eye re-simulates;
  // instead we snapshot the world and replay it per eye.
  const World start = world_;
  const int64_t shutter_ns = static_cast<int64_t>(std::llround(params_.sensor.shutter_s * 1e9));
  acc_.create(rig_.height_px(), rig_.width_px(), CV_32FC3);
  acc_.setTo(0);
  for (int i = 0; i < n; ++i) {
    const int64_t ts = t_ns - shutter_ns + shutter_ns * (i + 1) / n;
    world_.advance_to(ts);
    const LightKey light = lighting_at(scenario_, world_.time_ns() * 1e-9);
    renderer_.render(eye, world_.robot(), world_.ball(), light, sub_);
    cv::add(acc_, sub_, acc_, cv::noArray(), CV_32F);
  }
  acc_.convertTo(out, CV_8U, 1.0 / n);
  if (eye == Eye::kLeft) world_ = start;  // the right eye replays the same interval
}

}  // namespace stereoball::simulator
