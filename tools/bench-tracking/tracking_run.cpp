#include "tracking_run.hpp"

#include <cmath>

namespace stereoball::bench_tracking {
namespace {

namespace bd = ball_detector;

FrameRecord judge(const simulator::GroundTruth& g, const bd::StereoDetection& d,
                  const tracker::Track& track) {
  FrameRecord r;
  r.ball_present = g.ball_present;
  r.ball_visible = g.ball_present && g.ball_visible_left && g.ball_visible_right;
  r.ball_fully_visible = g.ball_present && g.ball_fully_visible_left && g.ball_fully_visible_right;
  r.raw_found = d.status == bd::DetectionStatus::kFound;
  r.accepted = tracker::is_accepted(track.verdict);
  r.stamp_ns = static_cast<std::int64_t>(std::llround(g.sim_time_s * 1e9));
  r.detection_status = bd::to_string(d.status);
  r.detection_reason = d.reason;
  r.verdict = std::string(tracker::to_string(track.verdict));
  r.verdict_reason = track.reason;
  r.track_state = std::string(tracker::to_string(track.state));
  r.found_left_x_px = d.left.x_px, r.found_left_y_px = d.left.y_px;
  r.found_radius_px = d.left.radius_px;
  r.no_ball_in_view = !r.ball_present;
  if (!r.ball_present) return r;
  r.true_left_x_px = g.ball_left_px.x, r.true_left_y_px = g.ball_left_px.y;
  const auto& c = g.ball_camera_m;
  r.true_distance_m = std::sqrt(c.x * c.x + c.y * c.y + c.z * c.z);
  if (r.raw_found) {
    // In 3D: a close ball's outline centre lies pixels away from where its centre projects
    // (10 px at 0.45 m), yet the detection is of the ball. Judged also when its centre is out
    // of one image (the ball entering or leaving the view): a detection of it is not off-ball.
    const double ex = d.position_m[0] - c.x, ey = d.position_m[1] - c.y, ez = d.position_m[2] - c.z;
    const double error_m = std::sqrt(ex * ex + ey * ey + ez * ez);
    r.raw_on_ball = error_m <= g.ball_radius_m;
    if (r.raw_on_ball && r.ball_visible) {  // the error table keeps to the visible ball
      r.error_m = error_m;
      r.error_xyz_m[0] = ex, r.error_xyz_m[1] = ey, r.error_xyz_m[2] = ez;
    }
  }
  r.accepted_on_ball = r.accepted && r.raw_on_ball;
  r.no_ball_in_view = !g.ball_visible_left && !g.ball_visible_right && !r.raw_on_ball;
  return r;
}

}  // namespace

RunOutcome run_scenario(const RunConfig& config, const FrameSink& on_frame) {
  RunOutcome out;
  out.result.scenario = config.scenario.name;
  auto loop = sim_loop::SimLoop::create(config);
  if (!loop) {
    out.error = loop.error();
    return out;
  }
  while ((*loop)->frames_done() < (*loop)->frame_count()) {
    const std::int64_t index = (*loop)->frames_done();
    const sim_loop::LoopFrame f = (*loop)->step();
    if (on_frame) on_frame(index, f);
    FrameRecord r = judge(f.truth, f.detection, f.track);
    r.cpu_ms = f.detector_cpu_ms;
    r.wall_ms = f.detector_wall_ms;
    out.result.frames.push_back(r);
  }
  return out;
}

}  // namespace stereoball::bench_tracking
