#include "closed_loop_run.hpp"

#include <cmath>

namespace stereoball::bench_closed_loop {

Sample to_sample(const sim_loop::LoopFrame& f) {
  Sample s;
  const simulator::GroundTruth& g = f.truth;
  s.truth.seq = g.frame_seq;
  s.truth.t_s = g.sim_time_s;
  s.truth.ball_present = g.ball_present;
  s.truth.visible = g.ball_present && g.ball_visible_left && g.ball_visible_right;
  s.truth.ball_cam_m[0] = g.ball_camera_m.x;
  s.truth.ball_cam_m[1] = g.ball_camera_m.y;
  s.truth.ball_cam_m[2] = g.ball_camera_m.z;
  s.truth.ball_world_m[0] = g.ball_world_m.x;
  s.truth.ball_world_m[1] = g.ball_world_m.y;
  s.truth.robot_world_m[0] = g.robot.x_m;
  s.truth.robot_world_m[1] = g.robot.y_m;
  s.truth.robot_yaw_rad = g.robot.yaw_rad;
  s.ball_speed_mps = std::hypot(f.ball_velocity_mps.x, f.ball_velocity_mps.y);
  s.detection.seq = g.frame_seq;
  s.detection.found = f.detection.status == ball_detector::DetectionStatus::kFound;
  for (int i = 0; i < 3; ++i) s.detection.position_m[i] = f.detection.position_m[i];
  s.track.seq = g.frame_seq;
  s.track.state = f.track.state;  // demo::TrackState is the tracker's own
  s.track.accepted = tracker::is_accepted(f.track.verdict);
  for (int i = 0; i < 3; ++i) s.track.position_m[i] = f.track.position_m[i];
  if (f.command) {
    s.searching = f.command->mode == motion_controller::Mode::kSearching;
    s.angular_radps = f.command->angular_radps;
    s.linear_mps = f.command->linear_mps;
  }
  return s;
}

Result<std::vector<Sample>> run_closed_loop(sim_loop::LoopConfig config) {
  config.drive = sim_loop::Drive::kController;
  auto loop = sim_loop::SimLoop::create(config);
  if (!loop) return Error{loop.error()};
  std::vector<Sample> samples;
  samples.reserve(static_cast<std::size_t>((*loop)->frame_count()));
  while ((*loop)->frames_done() < (*loop)->frame_count())
    samples.push_back(to_sample((*loop)->step()));
  return samples;
}

}  // namespace stereoball::bench_closed_loop
