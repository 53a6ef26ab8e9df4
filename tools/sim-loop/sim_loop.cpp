#include "sim_loop.hpp"

#include <algorithm>
#include <cmath>

#include "common/util/bench_clock.hpp"

namespace stereoball::sim_loop {
namespace {

namespace bd = ball_detector;
namespace mc = motion_controller;

tracker::Detection to_tracker(const bd::StereoDetection& d, int width_px) {
  tracker::Detection t;
  t.found = d.status == bd::DetectionStatus::kFound;
  t.position_m = {d.position_m[0], d.position_m[1], d.position_m[2]};
  t.left_x_px = d.left.x_px;
  t.image_width_px = static_cast<std::uint32_t>(width_px);
  t.patch_valid = d.patch_valid;
  std::copy(d.patch_rgb.begin(), d.patch_rgb.end(), t.patch_rgb.begin());
  return t;
}

}  // namespace

bd::TrackedBall to_tracked_ball(const tracker::Track& t, std::int64_t stamp_ns) {
  bd::TrackedBall b;
  b.following = t.state == tracker::TrackState::kFollowing;
  b.position_valid = t.position_valid;
  b.position_m = {t.position_m.x(), t.position_m.y(), t.position_m.z()};
  b.velocity_mps = {t.velocity_mps.x(), t.velocity_mps.y(), t.velocity_mps.z()};
  b.capture_stamp_ns = stamp_ns;
  return b;
}

mc::TrackSample to_controller(const tracker::Track& t, std::int64_t stamp_ns) {
  mc::TrackSample s;
  s.state = static_cast<mc::TrackState>(static_cast<int>(t.state));
  s.position_valid = t.position_valid;
  s.bearing_rad = t.bearing_rad;
  s.distance_m = t.distance_m;
  if (t.position_valid) {
    const mc::PolarRates r =
        mc::polar_rates(t.position_m.x(), t.position_m.z(), t.velocity_mps.x(), t.velocity_mps.z());
    s.bearing_rate_radps = r.bearing_radps;
    s.distance_rate_mps = r.range_mps;
  }
  s.last_seen_side = static_cast<mc::Side>(static_cast<int>(t.last_seen_side));
  s.capture_stamp_ns = stamp_ns;
  s.last_accepted_stamp_ns = t.last_accepted_stamp_ns;
  return s;
}

Result<std::unique_ptr<SimLoop>> SimLoop::create(const LoopConfig& config) {
  if (auto e = simulator::Simulator::check(config.sim, config.scenario))
    return Error{"scenario " + config.scenario.name + ": " + *e};
  if (auto e = config.tracker.validate()) return Error{"tracker parameters: " + *e};
  if (auto e = config.controller.validate()) return Error{"motion controller parameters: " + *e};
  if (!(config.controller_rate_hz >= 1.0 && config.controller_rate_hz <= 1000.0))
    return Error{"controller rate " + std::to_string(config.controller_rate_hz) +
                 " Hz is out of range [1, 1000]"};
  if (!(config.seconds > 0.0)) return Error{"run length must be positive seconds"};
  std::unique_ptr<SimLoop> loop(new SimLoop(config));
  if (auto e = loop->pipeline_.set_calibration(loop->sim_.calibration()))
    return Error{"calibration of the simulated rig: " + *e};
  return loop;
}

SimLoop::SimLoop(const LoopConfig& config)
    : config_(config),
      sim_(config.sim, config.scenario),
      pipeline_(config.detector),
      tracker_(config.tracker),
      controller_(config.controller),
      frame_period_ns_(sim_.frame_period_ns()),
      tick_period_ns_(static_cast<std::int64_t>(std::llround(1e9 / config.controller_rate_hz))),
      frame_count_(static_cast<std::int64_t>(config.seconds * 1e9 / frame_period_ns_)) {}

std::optional<simulator::VelocityCommand> SimLoop::scripted_command(std::int64_t t_ns) const {
  const auto c = simulator::scripted_command_at(config_.scenario, static_cast<double>(t_ns) * 1e-9);
  if (!c) return std::nullopt;
  return simulator::VelocityCommand{c->linear_mps, c->angular_radps, t_ns};
}

void SimLoop::run_controller_ticks(std::int64_t until_ns) {
  // A tick at the frame's own time does not see that frame yet: processing takes time.
  while (next_tick_ns_ <= until_ns) {
    const std::int64_t tick = next_tick_ns_;
    const mc::Command c = controller_.step(tick);
    // Move the world to the tick first, so the command acts from the tick time on.
    sim_.advance(std::nullopt, tick);
    sim_.advance(simulator::VelocityCommand{c.linear_mps, c.angular_radps, tick}, tick);
    last_command_ = c;
    last_command_ns_ = tick;
    next_tick_ns_ += tick_period_ns_;
  }
}

LoopFrame SimLoop::step() {
  const std::int64_t t_ns = next_frame_++ * frame_period_ns_;
  std::optional<simulator::VelocityCommand> command;
  if (config_.drive == Drive::kScript) {
    command = scripted_command(t_ns);
  } else {
    run_controller_ticks(t_ns);
  }
  const simulator::SimFrame f = sim_.step(command, t_ns);
  LoopFrame out;
  const double w0 = bench::wall_ms();
  const double c0 = bench::thread_cpu_ms();
  // The previous frame's track, as the node has it from ball/track when the frame arrives.
  const std::optional<bd::PositionPrior> prior =
      last_track_
          ? bd::prior_from_track(*last_track_, f.sim_time_ns, config_.detector.track_prior_gate_m,
                                 config_.detector.track_prior_max_age_ns)
          : std::nullopt;
  out.detection = pipeline_.step(f.left, f.right, false, prior, f.sim_time_ns);
  out.detector_cpu_ms = bench::thread_cpu_ms() - c0;
  out.detector_wall_ms = bench::wall_ms() - w0;
  out.track = tracker_.step(to_tracker(out.detection, f.left.cols), f.sim_time_ns);
  last_track_ = to_tracked_ball(out.track, f.sim_time_ns);
  if (config_.drive == Drive::kController) {
    controller_.on_track(to_controller(out.track, f.sim_time_ns), f.sim_time_ns);
  }
  out.truth = f.truth;
  out.left_raw = f.left;
  out.right_raw = f.right;
  out.ball_velocity_mps = sim_.world().ball().velocity_mps;
  out.command = last_command_;
  out.command_stamp_ns = last_command_ns_;
  return out;
}

}  // namespace stereoball::sim_loop
