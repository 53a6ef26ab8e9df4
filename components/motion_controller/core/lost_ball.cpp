#include "motion_controller/core/lost_ball.hpp"

#include <cmath>

namespace stereoball::motion_controller {

PlaneVector plane_velocity(const PlaneVector& p, const PolarRates& rates) {
  const double range = std::hypot(p.x, p.z);
  if (!(range > 1e-3)) return {};
  // x = r sin(b), z = r cos(b) with b = atan2(x, z).
  const double sin_b = p.x / range, cos_b = p.z / range;
  return {rates.range_mps * sin_b + range * rates.bearing_radps * cos_b,
          rates.range_mps * cos_b - range * rates.bearing_radps * sin_b};
}

namespace {

// The apparent velocity of a world-fixed point at p when the robot drives at own.linear_mps and
// turns left at own.angular_radps: a left turn sweeps points ahead to the right.
PlaneVector apparent_velocity(const PlaneVector& p, const Velocity& own) {
  return {own.angular_radps * p.z, -own.angular_radps * p.x - own.linear_mps};
}

}  // namespace

PlaneVector predict_lost_ball(const LostBall& ball) {
  const PlaneVector apparent = apparent_velocity(ball.last_m, ball.own_while_seen);
  const PlaneVector ball_velocity{ball.seen_velocity_mps.x - apparent.x,
                                  ball.seen_velocity_mps.z - apparent.z};
  // Where the ball is now, in the robot's frame of the last sighting.
  const PlaneVector moved{ball.last_m.x + ball_velocity.x * ball.age_s,
                          ball.last_m.z + ball_velocity.z * ball.age_s};
  // The robot's arc since then: a chord of length driven * sin(turn / 2) / (turn / 2), leaning
  // half the turn to the left.
  const double driven_m = ball.own_since.linear_mps * ball.age_s;
  const double turned_rad = ball.own_since.angular_radps * ball.age_s;
  const double half_turn = 0.5 * turned_rad;
  const double chord_m =
      std::abs(half_turn) > 1e-9 ? driven_m * std::sin(half_turn) / half_turn : driven_m;
  const double dx = moved.x + chord_m * std::sin(half_turn);
  const double dz = moved.z - chord_m * std::cos(half_turn);
  // Seen from axes turned left by turned_rad.
  const double c = std::cos(turned_rad), s = std::sin(turned_rad);
  return {dx * c + dz * s, -dx * s + dz * c};
}

}  // namespace stereoball::motion_controller
