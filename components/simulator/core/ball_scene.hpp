#pragma once
// A scene with one known ball seen by the simulated rig (raw distorted BGR images), for the
// ball detector's tests and benchmarks and the replay recordings.

#include <cstdint>

#include "simulator/core/simulator.hpp"

namespace stereoball::simulator {

/// Where the ball is and whether the room holds clutter.
struct SimBallSetup {
  double ball_x_m = 1.5;      ///< ball on the floor, metres ahead of the robot centre
  double ball_y_m = 0.0;      ///< metres to the left of the robot centre
  double vx_mps = 0.0;        ///< initial ball velocity along x, m/s
  double vy_mps = 0.0;        ///< initial ball velocity along y, m/s
  bool clutter = true;        ///< boxes, a door frame and a round plate in the room
  bool plain_room = false;    ///< untextured floor without grout lines or baseboard
  bool uniform_ball = false;  ///< one-colour ball (no white patches)
  std::uint64_t seed = 1;     ///< sensor noise seed
};

/// A scenario with the robot at the origin facing +x and the ball as described.
simulator::Scenario make_sim_scenario(const SimBallSetup& setup);

/// The simulator's hardware defaults (640x480, config/simulator.yaml values).
simulator::SimParams default_sim_params();

}  // namespace stereoball::simulator
