#include "simulator/node/ground_truth_msg.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace stereoball::simulator {
stereoball_msg_GroundTruth ground_truth_to_msg(const GroundTruth& g, int64_t stamp_ns,
                                               const std::string& scenario) {
  stereoball_msg_GroundTruth m{};
  m.frame_seq = g.frame_seq;
  m.stamp_ns = stamp_ns;
  m.sim_time_s = g.sim_time_s;
  m.scenario = const_cast<char*>(scenario.c_str());
  m.ball_present = g.ball_present;
  m.ball_radius_m = g.ball_radius_m;
  m.ball_world_m[0] = g.ball_world_m.x;
  m.ball_world_m[1] = g.ball_world_m.y;
  m.ball_world_m[2] = g.ball_world_m.z;
  m.ball_camera_m[0] = g.ball_camera_m.x;
  m.ball_camera_m[1] = g.ball_camera_m.y;
  m.ball_camera_m[2] = g.ball_camera_m.z;
  m.ball_visible_left = g.ball_visible_left;
  m.ball_visible_right = g.ball_visible_right;
  m.ball_left_px[0] = g.ball_left_px.x;
  m.ball_left_px[1] = g.ball_left_px.y;
  m.ball_right_px[0] = g.ball_right_px.x;
  m.ball_right_px[1] = g.ball_right_px.y;
  m.robot_x_m = g.robot.x_m;
  m.robot_y_m = g.robot.y_m;
  m.robot_yaw_rad = g.robot.yaw_rad;
  m.robot_linear_mps = g.robot.linear_mps;
  m.robot_angular_radps = g.robot.angular_radps;
  return m;
}

VelocityCommand command_from_msg(const stereoball_msg_VelocityCommand& msg, int64_t now_wall_ns,
                                 int64_t now_sim_ns, double rate) {
  // Saturating: any stamp (garbage included, found by fuzzing) gives an age in [0, 60 s]. A
  // command that old is stale and the base's gate has dropped it before this point anyway.
  constexpr int64_t kMaxAgeNs = 60'000'000'000;
  int64_t age_ns = 0;
  if (__builtin_sub_overflow(now_wall_ns, msg.stamp_ns, &age_ns))
    age_ns = msg.stamp_ns < 0 ? kMaxAgeNs : 0;  // far in the past, or far in the future
  age_ns = std::clamp<int64_t>(age_ns, 0, kMaxAgeNs);
  // The rate and clocks are the simulator's own (validated), but the arithmetic stays total.
  const double scale = std::isfinite(rate) && rate > 0.0 ? std::min(rate, 1e3) : 1.0;
  const auto sim_age_ns = static_cast<int64_t>(std::llround(static_cast<double>(age_ns) * scale));
  int64_t stamp_ns = 0;
  if (__builtin_sub_overflow(now_sim_ns, sim_age_ns, &stamp_ns))
    stamp_ns = std::numeric_limits<int64_t>::min();
  const double v = std::isfinite(msg.linear_mps) ? msg.linear_mps : 0.0;
  const double w = std::isfinite(msg.angular_radps) ? msg.angular_radps : 0.0;
  return {v, w, stamp_ns};
}

}  // namespace stereoball::simulator
