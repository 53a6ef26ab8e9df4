#include "simulator/io/ground_truth_csv.hpp"

#include <cstdio>

namespace stereoball::simulator {

std::string ground_truth_csv_header() {
  return "frame_seq,sim_time_s,ball_present,ball_radius_m,ball_world_x_m,ball_world_y_m,"
         "ball_world_z_m,ball_cam_x_m,ball_cam_y_m,ball_cam_z_m,ball_visible_left,"
         "ball_visible_right,ball_left_x_px,ball_left_y_px,ball_right_x_px,ball_right_y_px,"
         "robot_x_m,robot_y_m,robot_yaw_rad,robot_linear_mps,robot_angular_radps";
}

std::string ground_truth_csv_row(const GroundTruth& g) {
  char buf[512];
  std::snprintf(buf, sizeof(buf),
                "%llu,%.6f,%d,%.4f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%d,%d,%.3f,%.3f,%.3f,%.3f,%.6f,"
                "%.6f,%.6f,%.6f,%.6f",
                static_cast<unsigned long long>(g.frame_seq), g.sim_time_s, g.ball_present ? 1 : 0,
                g.ball_radius_m, g.ball_world_m.x, g.ball_world_m.y, g.ball_world_m.z,
                g.ball_camera_m.x, g.ball_camera_m.y, g.ball_camera_m.z,
                g.ball_visible_left ? 1 : 0, g.ball_visible_right ? 1 : 0, g.ball_left_px.x,
                g.ball_left_px.y, g.ball_right_px.x, g.ball_right_px.y, g.robot.x_m, g.robot.y_m,
                g.robot.yaw_rad, g.robot.linear_mps, g.robot.angular_radps);
  return buf;
}

}  // namespace stereoball::simulator
