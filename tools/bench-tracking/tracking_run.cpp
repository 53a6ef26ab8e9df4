#include "tracking_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <optional>

#include "ball_detector/node/stereo_pipeline.hpp"
#include "motion_controller/core/motion_controller.hpp"
#include "simulator/core/simulator.hpp"
#include "tracker/core/tracker.hpp"

namespace stereoball::bench_tracking {
namespace {

namespace bd = ball_detector;
namespace mc = motion_controller;

// CPU time of this thread, ms (does not grow when other processes load the machine).
double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

double wall_ms() {
  return std::chrono::duration<double, std::milli>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
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

mc::TrackSample to_controller(const tracker::Track& t, std::int64_t now_ns) {
  mc::TrackSample s;
  s.state = static_cast<mc::TrackState>(static_cast<int>(t.state));
  s.position_valid = t.position_valid;
  s.bearing_rad = t.bearing_rad;
  s.distance_m = t.distance_m;
  s.last_seen_side = static_cast<mc::Side>(static_cast<int>(t.last_seen_side));
  s.capture_stamp_ns = now_ns;
  s.last_accepted_stamp_ns = t.last_accepted_stamp_ns;
  return s;
}

FrameRecord judge(const simulator::GroundTruth& g, const bd::StereoDetection& d,
                  const tracker::Track& track) {
  FrameRecord r;
  r.ball_present = g.ball_present;
  r.ball_visible = g.ball_present && g.ball_visible_left && g.ball_visible_right;
  r.raw_found = d.status == bd::DetectionStatus::kFound;
  r.accepted = tracker::is_accepted(track.verdict);
  if (!r.ball_present) return r;
  const auto& c = g.ball_camera_m;
  r.true_distance_m = std::sqrt(c.x * c.x + c.y * c.y + c.z * c.z);
  if (r.raw_found && r.ball_visible) {
    const double dx = d.left.x_px - g.ball_left_px.x, dy = d.left.y_px - g.ball_left_px.y;
    r.raw_on_ball = std::sqrt(dx * dx + dy * dy) <= kOnBallPx;
  }
  if (r.raw_on_ball) {
    const double ex = d.position_m[0] - c.x, ey = d.position_m[1] - c.y, ez = d.position_m[2] - c.z;
    r.error_m = std::sqrt(ex * ex + ey * ey + ez * ez);
    r.error_xyz_m[0] = ex, r.error_xyz_m[1] = ey, r.error_xyz_m[2] = ez;
  }
  r.accepted_on_ball = r.accepted && r.raw_on_ball;
  return r;
}

}  // namespace

double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double rank = std::ceil(q * static_cast<double>(values.size()));
  const auto i = static_cast<std::size_t>(std::max(1.0, rank)) - 1;
  return values[std::min(i, values.size() - 1)];
}

RunOutcome run_scenario(const RunConfig& config) {
  RunOutcome out;
  out.result.scenario = config.scenario.name;
  if (auto e = simulator::Simulator::check(config.sim, config.scenario)) {
    out.error = "scenario " + config.scenario.name + ": " + *e;
    return out;
  }
  simulator::Simulator sim(config.sim, config.scenario);
  bd::StereoPipeline pipeline(config.detector);
  if (auto e = pipeline.set_calibration(sim.calibration())) {
    out.error = "calibration of the simulated rig: " + *e;
    return out;
  }
  tracker::Tracker tracker(config.tracker);
  mc::MotionController controller(config.controller);
  const std::int64_t period_ns = sim.frame_period_ns();
  const auto frames = static_cast<std::int64_t>(config.seconds * 1e9 / period_ns);
  std::optional<simulator::VelocityCommand> command;
  for (std::int64_t i = 0; i < frames; ++i) {
    const std::int64_t t_ns = i * period_ns;
    if (config.drive == Drive::kScript) {
      const auto c = simulator::scripted_command_at(config.scenario, t_ns * 1e-9);
      command = c ? std::optional(simulator::VelocityCommand{c->linear_mps, c->angular_radps, t_ns})
                  : std::nullopt;
    }
    const simulator::SimFrame f = sim.step(command, t_ns);
    const double w0 = wall_ms();
    const double c0 = thread_cpu_ms();
    const bd::StereoDetection d = pipeline.step(f.left, f.right, false);
    const double cpu = thread_cpu_ms() - c0;
    const double wall = wall_ms() - w0;
    const tracker::Track track = tracker.step(to_tracker(d, f.left.cols), t_ns);
    if (config.drive == Drive::kController) {
      controller.on_track(to_controller(track, t_ns), t_ns);
      const mc::Command c = controller.step(t_ns);
      command = simulator::VelocityCommand{c.linear_mps, c.angular_radps, t_ns};
    }
    FrameRecord r = judge(f.truth, d, track);
    r.cpu_ms = cpu;
    r.wall_ms = wall;
    out.result.frames.push_back(r);
  }
  return out;
}

}  // namespace stereoball::bench_tracking
