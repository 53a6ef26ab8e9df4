#include "simulator/core/world.hpp"

#include <algorithm>
#include <cmath>

namespace stereoball::simulator {
namespace {

double approach(double current, double target, double max_delta) {
  return current + std::clamp(target - current, -max_delta, max_delta);
}

// Moves current toward target: at the brake limit while |current| drops toward zero, at the
// acceleration limit otherwise. Reversing brakes to zero first and spends the rest of the step
// accelerating the other way.
double approach_braking(double current, double target, double accel_dt, double brake_dt) {
  if (current < 0.0) return -approach_braking(-current, -target, accel_dt, brake_dt);
  if (current == 0.0 || target >= current) return approach(current, target, accel_dt);
  const double lowest = std::max(target, 0.0);  // braking never crosses zero
  if (current - brake_dt > lowest) return current - brake_dt;
  if (target >= 0.0) return target;
  const double rest_of_step = 1.0 - current / brake_dt;  // fraction left after stopping
  return approach(0.0, target, accel_dt * rest_of_step);
}

constexpr double kNsPerS = 1e9;

}  // namespace

RobotBase::RobotBase(const RobotParams& params, const RobotState& start) : p_(params), s_(start) {
  s_.linear_mps = 0.0;
  s_.angular_radps = 0.0;
}

void RobotBase::step(double dt_s, int64_t now_ns) {
  double v_target = 0.0, w_target = 0.0;
  if (cmd_ && now_ns - cmd_->stamp_ns <= p_.command_timeout_ns) {
    v_target = std::clamp(cmd_->linear_mps, -p_.max_linear_mps, p_.max_linear_mps);
    w_target = std::clamp(cmd_->angular_radps, -p_.max_angular_radps, p_.max_angular_radps);
  }
  const double v0 = s_.linear_mps, w0 = s_.angular_radps;
  s_.linear_mps = approach_braking(v0, v_target, p_.max_linear_accel_mps2 * dt_s,
                                   p_.max_linear_brake_mps2 * dt_s);
  s_.angular_radps = approach_braking(w0, w_target, p_.max_angular_accel_radps2 * dt_s,
                                      p_.max_angular_brake_radps2 * dt_s);
  // Trapezoidal velocities over the step, then the exact arc for constant (v, w).
  const double v = 0.5 * (v0 + s_.linear_mps), w = 0.5 * (w0 + s_.angular_radps);
  const double yaw0 = s_.yaw_rad;
  const double yaw1 = yaw0 + w * dt_s;
  if (std::abs(w) < 1e-9) {
    s_.x_m += v * dt_s * std::cos(yaw0);
    s_.y_m += v * dt_s * std::sin(yaw0);
  } else {
    s_.x_m += v / w * (std::sin(yaw1) - std::sin(yaw0));
    s_.y_m -= v / w * (std::cos(yaw1) - std::cos(yaw0));
  }
  s_.yaw_rad = std::remainder(yaw1, 2.0 * M_PI);
}

World::World(const SimParams& params, const Scenario& scenario)
    : p_(params),
      sc_(scenario),
      robot_(params.robot,
             RobotState{scenario.robot_x_m, scenario.robot_y_m, scenario.robot_yaw_rad, 0.0, 0.0}) {
  if (scenario.ball) {
    const BallSpec& b = *scenario.ball;
    ball_.present = true;
    ball_.radius_m = b.radius_m;
    ball_.position_m = {b.x_m, b.y_m, b.radius_m};
    ball_.velocity_mps = {b.vx_mps, b.vy_mps, 0.0};
  }
  apply_kicks();
}

void World::advance_to(int64_t t_ns) {
  const int64_t step_ns = static_cast<int64_t>(std::llround(p_.ball.physics_step_s * kNsPerS));
  while (t_ns_ < t_ns) {
    const int64_t dt_ns = std::min(step_ns, t_ns - t_ns_);
    robot_.step(dt_ns / kNsPerS, t_ns_);
    keep_robot_in_room();
    step_ball(dt_ns / kNsPerS);
    t_ns_ += dt_ns;
    apply_kicks();
  }
}

void World::apply_kicks() {
  while (next_kick_ < sc_.kicks.size() &&
         static_cast<int64_t>(std::llround(sc_.kicks[next_kick_].t_s * kNsPerS)) <= t_ns_) {
    const KickSpec& k = sc_.kicks[next_kick_++];
    ball_.velocity_mps = {k.vx_mps, k.vy_mps, 0.0};
  }
}

void World::step_ball(double dt_s) {
  if (!ball_.present) return;
  Vec3d& v = ball_.velocity_mps;
  const double speed = std::hypot(v.x, v.y);
  if (speed > 0.0) {
    const double new_speed = std::max(0.0, speed - p_.ball.rolling_decel_mps2 * dt_s);
    const double avg = 0.5 * (speed + new_speed);
    const Vec3d dir{v.x / speed, v.y / speed, 0.0};
    ball_.position_m = ball_.position_m + dir * (avg * dt_s);
    v = dir * new_speed;
    // Rolling without slipping: spin axis z x v, angle = distance / radius.
    const Vec3d axis = Vec3d{0, 0, 1}.cross(dir);
    ball_.orientation = Mat3::rodrigues(axis * (avg * dt_s / ball_.radius_m)) * ball_.orientation;
  }
  collide_ball_with_room();
  collide_ball_with_boxes();
  collide_ball_with_robot();
}

void World::collide_ball_with_room() {
  const RoomSpec& r = sc_.room;
  const double rad = ball_.radius_m, e = p_.ball.restitution;
  Vec3d& p = ball_.position_m;
  Vec3d& v = ball_.velocity_mps;
  if (p.x < r.x_min_m + rad) p.x = r.x_min_m + rad, v.x = std::abs(v.x) * e;
  if (p.x > r.x_max_m - rad) p.x = r.x_max_m - rad, v.x = -std::abs(v.x) * e;
  if (p.y < r.y_min_m + rad) p.y = r.y_min_m + rad, v.y = std::abs(v.y) * e;
  if (p.y > r.y_max_m - rad) p.y = r.y_max_m - rad, v.y = -std::abs(v.y) * e;
}

void World::collide_ball_with_boxes() {
  const double rad = ball_.radius_m, e = p_.ball.restitution;
  Vec3d& p = ball_.position_m;
  Vec3d& v = ball_.velocity_mps;
  for (const BoxSpec& b : sc_.boxes) {
    if (b.z_m > 2.0 * rad) continue;  // ball rolls underneath
    const double hx = 0.5 * b.size_x_m + rad, hy = 0.5 * b.size_y_m + rad;
    const double dx = p.x - b.x_m, dy = p.y - b.y_m;
    if (std::abs(dx) >= hx || std::abs(dy) >= hy) continue;
    // Push out along the axis of least penetration and reflect that component.
    if (hx - std::abs(dx) < hy - std::abs(dy)) {
      const double s = dx >= 0 ? 1.0 : -1.0;
      p.x = b.x_m + s * hx;
      v.x = s * std::abs(v.x) * e;
    } else {
      const double s = dy >= 0 ? 1.0 : -1.0;
      p.y = b.y_m + s * hy;
      v.y = s * std::abs(v.y) * e;
    }
  }
}

void World::collide_ball_with_robot() {
  const RobotState& r = robot_.state();
  const double min_d = ball_.radius_m + p_.robot.radius_m;
  Vec3d d{ball_.position_m.x - r.x_m, ball_.position_m.y - r.y_m, 0.0};
  const double dist = d.norm();
  if (dist >= min_d || dist < 1e-9) return;
  const Vec3d n = d * (1.0 / dist);
  ball_.position_m = ball_.position_m + n * (min_d - dist);
  // Reflect the ball's velocity relative to the robot's, so a pushing robot nudges the ball.
  const Vec3d vr{r.linear_mps * std::cos(r.yaw_rad), r.linear_mps * std::sin(r.yaw_rad), 0.0};
  const Vec3d rel = ball_.velocity_mps - vr;
  const double vn = rel.dot(n);
  if (vn < 0.0) ball_.velocity_mps = ball_.velocity_mps - n * ((1.0 + p_.ball.restitution) * vn);
}

void World::keep_robot_in_room() {
  const RoomSpec& room = sc_.room;
  const RobotState& s = robot_.state();
  const double m = p_.robot.radius_m;
  robot_.set_position(std::clamp(s.x_m, room.x_min_m + m, room.x_max_m - m),
                      std::clamp(s.y_m, room.y_min_m + m, room.y_max_m - m));
}

}  // namespace stereoball::simulator
