#pragma once
// Where a ball that left the view is now: the side the search turns to. Predicted as a point
// moving in the floor plane, not as a bearing moving at a constant rate: a ball rolling past
// the robot close by swings from one side of the camera axis to the other, and a rate seen
// from the camera (off the robot's centre) can point the other way than the ball goes.

#include "motion_controller/core/own_motion.hpp"
#include "motion_controller/core/types.hpp"

namespace stereoball::motion_controller {

/// A point or velocity in the floor plane: x to the right, z forward (metres, or m/s).
struct PlaneVector {
  double x = 0.0;
  double z = 0.0;
};

/// Velocity of a point at p with the given bearing and range rates (the inverse of
/// polar_rates); zero at the origin.
PlaneVector plane_velocity(const PlaneVector& p, const PolarRates& rates);

/// What is known of a ball the camera no longer sees.
struct LostBall {
  PlaneVector last_m;             ///< last accepted position from the robot's centre, m
  PlaneVector seen_velocity_mps;  ///< its velocity as the camera saw it (own motion included)
  Velocity own_while_seen;        ///< the robot's own velocity behind that seen velocity
  double age_s = 0.0;             ///< time since the last accepted position, s
  Velocity own_since;             ///< the robot's mean velocity since then
};

/// The ball's position now from the robot's centre: moved on at its own velocity (the seen one
/// less what the robot's motion made it seem) and seen from where the robot has since driven
/// and turned (a constant-rate arc).
PlaneVector predict_lost_ball(const LostBall& ball);

}  // namespace stereoball::motion_controller
