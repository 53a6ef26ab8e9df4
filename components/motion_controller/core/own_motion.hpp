#pragma once
// The robot's own commanded velocities over the recent past: rates the camera saw over a span
// of time contain the robot's motion over that span, not its present velocity.

#include <cstdint>
#include <deque>

namespace stereoball::motion_controller {

/// Linear (m/s) and angular (rad/s, positive = left) velocity.
struct Velocity {
  double linear_mps = 0.0;
  double angular_radps = 0.0;
};

/// Piecewise-constant history of the commands the controller issued.
class OwnMotionHistory {
 public:
  /// Records the velocity in force from t_ns on (t_ns non-decreasing), ns.
  void record(std::int64_t t_ns, const Velocity& v);
  /// Forgets what ended before t_ns (the velocity in force at t_ns is kept), ns.
  void forget_before(std::int64_t t_ns);
  /// Velocity in force at t_ns (zero before the first record).
  Velocity at(std::int64_t t_ns) const;
  /// Mean over [from_ns, to_ns] weighted by (t - from)(to - t), the weights a least-squares
  /// slope of a quantity over that span gives its rate of change; at(to_ns) if the span is
  /// empty.
  Velocity slope_weighted_mean(std::int64_t from_ns, std::int64_t to_ns) const;
  /// Plain time average over [from_ns, to_ns] (at(to_ns) if the span is empty).
  Velocity mean(std::int64_t from_ns, std::int64_t to_ns) const;

 private:
  Velocity weighted_mean(std::int64_t from_ns, std::int64_t to_ns, bool slope_weights) const;

  struct Entry {
    std::int64_t t_ns = 0;
    Velocity v;
  };
  std::deque<Entry> entries_;
};

}  // namespace stereoball::motion_controller
