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
      occluders_(occluders_of(scenario)) {
  if (scenario.calibration) {
    board_scene_ = with_drawn_holds(*scenario.calibration, rig_);
    board_renderer_.emplace(rig_, *board_scene_);
  }
}

Status Simulator::check(const SimParams& params, const Scenario& scenario) {
  if (auto st = params.validate(); !st) return Error{"simulator params: " + st.error()};
  if (auto e = scenario.validate(); !e)
    return Error{"scenario '" + scenario.name + "': " + e.error()};
  return {};
}

int64_t Simulator::frame_period_ns() const {
  return static_cast<int64_t>(std::llround(1e9 / params_.frame_rate_hz));
}

void Simulator::advance(const std::optional<VelocityCommand>& command, int64_t sim_time_ns) {
  if (command) world_.set_command(*command);
  world_.advance_to(sim_time_ns);
}

void run_in_turn(const std::function<void()>& a, const std::function<void()>& b) {
  a();
  b();
}

SimFrame Simulator::step(const std::optional<VelocityCommand>& command, int64_t sim_time_ns,
                         const RunBoth& run_both) {
  if (command) world_.set_command(*command);
  SimFrame f;
  f.seq = seq_++;
  f.sim_time_ns = std::max(sim_time_ns, world_.time_ns());
  f.right_time_ns = f.sim_time_ns;
  if (board_scene_) {
    f.right_time_ns += static_cast<int64_t>(std::llround(board_scene_->eye_skew_s * 1e9));
    step_board(f);
    return f;
  }
  run_both([&] { render_eye(Eye::kLeft, world_, f.sim_time_ns, f.left); },
           [&] { render_eye(Eye::kRight, world_, f.sim_time_ns, f.right); });
  // The world takes the same steps as the eyes' copies did (physics steps end at each time).
  for (int64_t ts : exposure_times(f.sim_time_ns)) world_.advance_to(ts);
  sensor_.apply(f.left);
  sensor_.apply(f.right);
  f.truth =
      make_ground_truth(rig_, world_.robot(), world_.ball(), f.seq, f.sim_time_ns, occluders_);
  return f;
}

void Simulator::step_board(SimFrame& f) {
  const CalibrationScene& scene = *board_scene_;
  BoardTruth truth;
  truth.left_pose = board_pose_at(scene, f.sim_time_ns * 1e-9);
  truth.right_pose = board_pose_at(scene, f.right_time_ns * 1e-9);
  truth.left_hold = hold_index_at(scene, f.sim_time_ns * 1e-9);
  truth.right_hold = hold_index_at(scene, f.right_time_ns * 1e-9);
  board_renderer_->render(Eye::kLeft, truth.left_pose, f.left);
  board_renderer_->render(Eye::kRight, truth.right_pose, f.right);
  world_.advance_to(f.sim_time_ns);
  sensor_.apply(f.left);
  sensor_.apply(f.right);
  f.truth = make_ground_truth(rig_, world_.robot(), world_.ball(), f.seq, f.sim_time_ns);
  f.board = truth;
}

std::vector<int64_t> Simulator::exposure_times(int64_t t_ns) const {
  // Motion blur: n renders spread over the shutter interval ending at t_ns.
  const int n = std::max(1, params_.sensor.motion_blur_subframes);
  if (n == 1) return {t_ns};
  const int64_t shutter_ns = static_cast<int64_t>(std::llround(params_.sensor.shutter_s * 1e9));
  std::vector<int64_t> times;
  for (int i = 0; i < n; ++i) times.push_back(t_ns - shutter_ns + shutter_ns * (i + 1) / n);
  return times;
}

void Simulator::render_eye(Eye eye, World world, int64_t t_ns, cv::Mat& out) {
  const std::vector<int64_t> times = exposure_times(t_ns);
  const auto render_at = [&](int64_t ts, cv::Mat& into) {
    world.advance_to(ts);
    const LightKey light = lighting_at(scenario_, world.time_ns() * 1e-9);
    renderer_.render(eye, world.robot(), world.ball(), light, into);
  };
  if (times.size() == 1) return render_at(times[0], out);
  const int e = static_cast<int>(eye);
  acc_[e].create(rig_.height_px(), rig_.width_px(), CV_32FC3);
  acc_[e].setTo(0);
  for (int64_t ts : times) {
    render_at(ts, sub_[e]);
    cv::add(acc_[e], sub_[e], acc_[e], cv::noArray(), CV_32F);
  }
  acc_[e].convertTo(out, CV_8U, 1.0 / static_cast<double>(times.size()));
}

}  // namespace stereoball::simulator
