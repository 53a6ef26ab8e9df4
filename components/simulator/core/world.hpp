#pragma once
// World dynamics: a differential-drive robot and a rolling ball in a room; time is an argument.

#include <cstdint>
#include <optional>

#include "simulator/core/scenario.hpp"
#include "simulator/core/sim_params.hpp"
#include "simulator/core/vec3.hpp"

namespace stereoball::simulator {

/// A velocity command for the base, stamped in simulated time.
struct VelocityCommand {
  double linear_mps = 0.0;     ///< forward speed, m/s
  double angular_radps = 0.0;  ///< yaw rate, rad/s, positive = turn left
  int64_t stamp_ns = 0;        ///< simulated time the command was issued, ns
};

/// Robot pose in the world (x forward, y left, z up) and its actual velocity.
struct RobotState {
  double x_m = 0.0, y_m = 0.0, yaw_rad = 0.0;
  double linear_mps = 0.0, angular_radps = 0.0;
};

/// The ball: centre in the world, velocity, and orientation of its texture.
struct BallState {
  bool present = false;
  double radius_m = 0.11;
  Vec3d position_m;    ///< centre, world metres (z = radius on the floor)
  Vec3d velocity_mps;  ///< world m/s
  Mat3 orientation;    ///< world-from-ball rotation (the texture rolls with the ball)
};

/// Robot base with velocity/acceleration limits and a stale-command stop.
class RobotBase {
 public:
  /// Base at the given start pose, at rest.
  RobotBase(const RobotParams& params, const RobotState& start);
  /// Latest command; replaces the previous one.
  void set_command(const VelocityCommand& cmd) { cmd_ = cmd; }
  /// Integrates from now_ns over dt_s seconds (now_ns decides command staleness).
  void step(double dt_s, int64_t now_ns);
  /// Current pose and velocity.
  const RobotState& state() const { return s_; }
  /// Overrides the pose (used to keep the base inside the room).
  void set_position(double x_m, double y_m) { s_.x_m = x_m, s_.y_m = y_m; }

 private:
  RobotParams p_;
  RobotState s_;
  std::optional<VelocityCommand> cmd_;
};

/// Robot + ball + room; advance_to() integrates with a fixed step for determinism.
class World {
 public:
  /// World at scenario start (t = 0).
  World(const SimParams& params, const Scenario& scenario);
  /// Passes a velocity command to the base.
  void set_command(const VelocityCommand& cmd) { robot_.set_command(cmd); }
  /// Integrates up to t_ns (simulated time since start); earlier times are ignored.
  void advance_to(int64_t t_ns);
  /// Current simulated time, ns.
  int64_t time_ns() const { return t_ns_; }
  /// Robot state.
  const RobotState& robot() const { return robot_.state(); }
  /// Ball state (present = false when the scenario has no ball).
  const BallState& ball() const { return ball_; }

 private:
  void step(double dt_s);
  void apply_kicks();
  void step_ball(double dt_s);
  void collide_ball_with_room();
  void collide_ball_with_boxes();
  void collide_ball_with_robot();
  void keep_robot_in_room();

  SimParams p_;
  Scenario sc_;
  RobotBase robot_;
  BallState ball_;
  int64_t t_ns_ = 0;
  size_t next_kick_ = 0;
};

}  // namespace stereoball::simulator
