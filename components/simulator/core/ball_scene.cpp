#include "simulator/core/ball_scene.hpp"

namespace stereoball::simulator {

simulator::Scenario make_sim_scenario(const SimBallSetup& setup) {
  simulator::Scenario s;
  s.name = "ball_detector_test";
  s.seed = setup.seed;
  s.duration_s = 60.0;
  simulator::BallSpec ball;
  ball.x_m = setup.ball_x_m;
  ball.y_m = setup.ball_y_m;
  ball.vx_mps = setup.vx_mps;
  ball.vy_mps = setup.vy_mps;
  if (setup.uniform_ball) ball.color_b = ball.color_a;
  s.ball = ball;
  s.room.plain = setup.plain_room;
  if (setup.clutter) {
    s.boxes.push_back({3.2, 1.6, 0.5, 0.6, 0.45, 0.0, {150, 110, 70}});
    s.boxes.push_back({4.5, -2.2, 0.8, 0.6, 0.9, 0.0, {70, 100, 140}});
    s.boxes.push_back({2.6, -2.5, 0.4, 0.4, 0.3, 0.0, {90, 140, 80}});
    simulator::DoorFrameSpec door;
    door.x_m = 6.0;
    door.y_m = -0.8;
    s.door_frames.push_back(door);
    simulator::PlateSpec plate;
    plate.center_m = {5.99, 1.3, 1.4};
    plate.radius_m = 0.15;
    s.plates.push_back(plate);
  }
  return s;
}

simulator::SimParams default_sim_params() {
  return simulator::SimParams{};
}

}  // namespace stereoball::simulator
