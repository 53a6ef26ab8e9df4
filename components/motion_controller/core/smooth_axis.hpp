#pragma once
// A velocity that follows its target within velocity, acceleration and jerk
// limits: the command never jumps, and its acceleration never jumps either. Slowing down may
// use a harder limit than speeding up (a base brakes harder than it accelerates, and a robot
// closing in on a ball that turned toward it must stop short of it).

namespace stereoball::motion_controller {

/// Limits of one axis, in the axis unit (m or rad) per s, s^2, s^3.
struct AxisLimits {
  double max_velocity = 1.0;   ///< highest velocity
  double min_velocity = -1.0;  ///< lowest velocity (negative for reverse)
  double max_accel = 1.0;      ///< |acceleration| bound while |velocity| grows, > 0
  double max_jerk = 10.0;      ///< |jerk| bound, > 0
  double max_brake = 1.0;      ///< |acceleration| bound while |velocity| drops, > 0
};

/// Jerk-limited tracking of a velocity target by one axis.
class SmoothAxis {
 public:
  /// limits: max_accel, max_brake and max_jerk must be > 0, min_velocity <= max_velocity.
  explicit SmoothAxis(const AxisLimits& limits) : limits_(limits) {}

  /// Advances by dt_s seconds toward target (clamped to the limits); returns the velocity.
  double step(double target, double dt_s);
  /// Sets velocity and acceleration to zero at once (emergency / stale stop).
  void reset();
  /// Current velocity.
  double velocity() const { return velocity_; }
  /// Current acceleration.
  double accel() const { return accel_; }

 private:
  AxisLimits limits_;
  double velocity_ = 0.0;
  double accel_ = 0.0;
};

}  // namespace stereoball::motion_controller
