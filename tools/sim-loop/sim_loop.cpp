#include "sim_loop.hpp"

#include <algorithm>
#include <cmath>

#include "common/util/bench_clock.hpp"

namespace stereoball::sim_loop {
namespace {

namespace bd = ball_detector;
namespace mc = motion_controller;

// The controller's clock is simulated time moved on by 1 s: the first frame is exposed at
// simulated time 0, and a capture stamp of 0 means "never set" to the controller.
constexpr std::int64_t kControllerClockOffsetNs = 1'000'000'000;

mc::TrackSample on_controller_clock(mc::TrackSample s) {
  s.capture_stamp_ns += kControllerClockOffsetNs;
  s.last_accepted_stamp_ns += kControllerClockOffsetNs;
  return s;
}

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
  if (auto st = config.tracker.validate(); !st) return Error{"tracker parameters: " + st.error()};
  if (auto st = config.controller.validate(); !st)
    return Error{"motion controller parameters: " + st.error()};
  if (!(config.controller_rate_hz >= 1.0 && config.controller_rate_hz <= 1000.0))
    return Error{"controller rate " + std::to_string(config.controller_rate_hz) +
                 " Hz is out of range [1, 1000]"};
  if (!(config.seconds > 0.0)) return Error{"run length must be positive seconds"};
  if (config.control_latency_ns < 0 || config.control_latency_ns > 1'000'000'000)
    return Error{"control latency " + std::to_string(config.control_latency_ns) +
                 " ns is out of range [0, 1 s]"};
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

void SimLoop::run_controller_until(std::int64_t until_ns) {
  // A command at the frame's own time does not see that frame yet: processing takes time.
  while (true) {
    const std::int64_t minimum_rate_ns =
        last_command_ns_ < 0 ? 0 : last_command_ns_ + tick_period_ns_;
    const bool track_first =
        !pending_tracks_.empty() && pending_tracks_.front().arrival_ns <= minimum_rate_ns;
    if (track_first && pending_tracks_.front().arrival_ns <= until_ns) {
      const PendingTrack p = pending_tracks_.front();
      pending_tracks_.pop_front();
      const auto response = controller_.on_track(p.sample, p.arrival_ns + kControllerClockOffsetNs);
      if (response.command) apply(*response.command, p.arrival_ns);
    } else if (!track_first && minimum_rate_ns <= until_ns) {
      apply(controller_.step(minimum_rate_ns + kControllerClockOffsetNs), minimum_rate_ns);
    } else {
      return;
    }
  }
}

void SimLoop::apply(const mc::Command& c, std::int64_t at_ns) {
  // Move the world to the command's time first, so the command acts from then on.
  sim_.advance(std::nullopt, at_ns);
  sim_.advance(simulator::VelocityCommand{c.linear_mps, c.angular_radps, at_ns}, at_ns);
  last_command_ = c;
  last_command_ns_ = at_ns;
}

LoopFrame SimLoop::step() {
  const std::int64_t t_ns = next_frame_++ * frame_period_ns_;
  std::optional<simulator::VelocityCommand> command;
  if (config_.drive == Drive::kScript) {
    command = scripted_command(t_ns);
  } else {
    run_controller_until(t_ns);
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
  // As the node does after publishing; its cost is the detector's too (same core), though
  // no answer waits for it.
  const double c1 = bench::thread_cpu_ms(), w1 = bench::wall_ms();
  pipeline_.finish_frame(f.left, false);
  out.detector_cpu_ms += bench::thread_cpu_ms() - c1;
  out.detector_wall_ms += bench::wall_ms() - w1;
  out.track = tracker_.step(to_tracker(out.detection, f.left.cols), f.sim_time_ns);
  last_track_ = to_tracked_ball(out.track, f.sim_time_ns);
  if (config_.drive == Drive::kController) {
    pending_tracks_.push_back({on_controller_clock(to_controller(out.track, f.sim_time_ns)),
                               f.sim_time_ns + config_.control_latency_ns});
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
