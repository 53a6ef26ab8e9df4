#include "sim_loop.hpp"

#include <algorithm>
#include <cmath>

#include "ball_detector/node/detection_msg.hpp"
#include "common/util/bench_clock.hpp"
#include "motion_controller/node/command_msg.hpp"
#include "tracker/node/track_msg.hpp"

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

// The detection as the tracker node receives it: through ball/detection and the two nodes'
// conversions (a FOUND message with a bad position is not a detection).
tracker::Detection to_tracker(const bd::StereoDetection& d, std::uint64_t seq,
                              std::int64_t stamp_ns, int width_px) {
  stereoball_msg_BallDetection msg{};
  bd::to_message(d, {seq, stamp_ns}, 0.0F, stamp_ns, msg);
  return tracker::to_detection(msg, static_cast<std::uint32_t>(width_px)).detection;
}

}  // namespace

stereoball_msg_BallTrack track_message(const tracker::Track& track, std::uint64_t seq,
                                       std::int64_t stamp_ns) {
  stereoball_msg_BallTrack msg{};
  tracker::to_message(track, seq, stamp_ns, stamp_ns, msg);
  return msg;
}

bd::TrackedBall to_tracked_ball(const tracker::Track& t, std::int64_t stamp_ns) {
  return bd::from_message(track_message(t, 0, stamp_ns));
}

mc::TrackSample to_controller(const tracker::Track& t, std::int64_t stamp_ns) {
  return mc::to_sample(track_message(t, 0, stamp_ns));
}

Result<std::unique_ptr<SimLoop>> SimLoop::create(const LoopConfig& config) {
  if (auto e = simulator::Simulator::check(config.sim, config.scenario); !e)
    return Error{"scenario " + config.scenario.name + ": " + e.error()};
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
  if (auto e = loop->pipeline_.set_calibration(loop->sim_.calibration()); !e)
    return Error{"calibration of the simulated rig: " + e.error()};
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
  out.track =
      tracker_.step(to_tracker(out.detection, f.seq, f.sim_time_ns, f.left.cols), f.sim_time_ns);
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
