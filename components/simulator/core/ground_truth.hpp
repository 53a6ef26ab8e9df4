#pragma once
// Ground truth of one simulated frame: where the ball really is, and the robot.

#include <cstdint>
#include <string>
#include <vector>

#include "simulator/core/rig.hpp"
#include "simulator/core/scenario.hpp"
#include "simulator/core/world.hpp"

namespace stereoball::simulator {

/// True state at a rendered frame (mirrors the sim/ground_truth message).
struct GroundTruth {
  uint64_t frame_seq = 0;
  double sim_time_s = 0.0;    ///< simulated time since scenario start, seconds
  bool ball_present = false;  ///< the scenario has a ball at all
  double ball_radius_m = 0.0;
  Vec3d ball_world_m;   ///< ball centre, world frame, metres
  Vec3d ball_camera_m;  ///< ball centre, left rectified camera frame (x right, y down, z fwd)
  bool ball_visible_left = false;  ///< centre in front of the camera and inside the image
  bool ball_visible_right = false;
  /// The whole ball in view: its rectified outline (10 % slack) inside the image and the lines
  /// of sight to its centre and four rim points unblocked (centre visibility is the fields above).
  bool ball_fully_visible_left = false;
  bool ball_fully_visible_right = false;
  Point2 ball_left_px;   ///< projected centre, rectified left image, pixels
  Point2 ball_right_px;  ///< projected centre, rectified right image, pixels
  RobotState robot;      ///< pose and actual velocity
};

/// Ball centre in a camera's own (unrectified) frame, metres.
Vec3d world_to_camera(const StereoRig& rig, Eye eye, const RobotState& robot, const Vec3d& p_world);

/// What can hide the ball from a camera: solid boxes (boxes, door frames) and the distractor
/// spheres (other balls, round things on boxes). Plates hang on walls, behind any ball.
struct Occluders {
  std::vector<SolidBox> boxes;
  std::vector<SphereSpec> spheres;
};

/// Every solid box and every sphere of the scenario.
Occluders occluders_of(const Scenario& s);

/// Ground truth for the given state; visibility requires the centre in front of the eye,
/// inside both its raw and rectified image, and not hidden behind any of occluders.
GroundTruth make_ground_truth(const StereoRig& rig, const RobotState& robot, const BallState& ball,
                              uint64_t frame_seq, int64_t sim_time_ns,
                              const Occluders& occluders = {});

/// True if the segment from a to b (world, metres) passes through any of the boxes.
bool segment_blocked(const std::vector<SolidBox>& boxes, const Vec3d& a, const Vec3d& b);

/// True if the segment from a to b (world, metres) passes through any of the spheres.
bool segment_blocked(const std::vector<SphereSpec>& spheres, const Vec3d& a, const Vec3d& b);

}  // namespace stereoball::simulator
