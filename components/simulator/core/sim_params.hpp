#pragma once
// Parameters of the simulated hardware: cameras, rig, robot base, ball physics, sensor.
// The scene itself (room, clutter, ball, script) is a Scenario (scenario.hpp).

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "simulator/core/vec3.hpp"

namespace stereoball::simulator {

/// One camera of the rig: intrinsics derived from the field of view, plus lens distortion.
struct EyeParams {
  double hfov_deg = 62.0;              ///< horizontal field of view of the pinhole part, degrees
  double fy_over_fx = 1.0;             ///< pixel aspect ratio fy / fx
  double cx_offset_px = 0.0;           ///< principal point offset from the image centre, pixels
  double cy_offset_px = 0.0;           ///< principal point offset from the image centre, pixels
  std::array<double, 5> distortion{};  ///< OpenCV order k1 k2 p1 p2 k3, unitless
  double gain = 1.0;                   ///< sensor gain of this eye relative to nominal
};

/// Stereo rig geometry and its mounting on the robot.
struct RigParams {
  double baseline_m = 0.12;  ///< ideal distance between the optical centres, metres
  double height_m = 0.30;    ///< optical centre height above the floor, metres
  double forward_m = 0.10;   ///< optical centre ahead of the robot centre, metres
  double tilt_rad = 0.20;    ///< downward pitch of the rig, radians (positive = down)
  Vec3d right_rotation_error_rad{0.004, -0.006, 0.003};  ///< right camera mis-rotation (x,y,z)
  Vec3d right_offset_error_m{0.0, 0.002, -0.0015};       ///< right camera mis-placement, metres
  double rectify_alpha = 0.0;  ///< cv::stereoRectify alpha: 0 = only valid pixels, 1 = all
};

/// Differential-drive base limits.
struct RobotParams {
  double max_linear_mps = 1.0;               ///< |forward speed| limit, m/s
  double max_angular_radps = 2.0;            ///< |yaw rate| limit, rad/s
  double max_linear_accel_mps2 = 1.5;        ///< |forward acceleration| limit, m/s^2
  double max_angular_accel_radps2 = 6.0;     ///< |yaw acceleration| limit, rad/s^2
  double max_linear_brake_mps2 = 4.0;        ///< |deceleration| limit while |speed| drops, m/s^2
  double max_angular_brake_radps2 = 16.0;    ///< |yaw deceleration| limit while |rate| drops
  int64_t command_timeout_ns = 300'000'000;  ///< commands older than this stop the base, ns
  double radius_m = 0.20;                    ///< footprint radius (walls, ball contact), metres
};

/// Ball physics.
struct BallPhysicsParams {
  double rolling_decel_mps2 = 0.12;  ///< constant deceleration of a rolling ball, m/s^2
  double restitution = 0.7;          ///< fraction of normal speed kept after a bounce
  double physics_step_s = 0.002;     ///< integration step of the world, seconds
};

/// Image sensor effects.
struct SensorParams {
  double noise_sigma_dn = 2.0;    ///< Gaussian read noise, digital numbers (0..255 scale)
  int motion_blur_subframes = 1;  ///< renders averaged per frame (1 = no motion blur)
  double shutter_s = 0.012;       ///< exposure time spanned by the motion blur, seconds
};

/// Everything about the simulated hardware.
struct SimParams {
  int width_px = 640;           ///< image width, pixels
  int height_px = 480;          ///< image height, pixels
  double frame_rate_hz = 30.0;  ///< stereo frames per simulated second
  EyeParams left{62.0, 1.0, 3.2, -2.4, {-0.12, 0.035, 0.0004, -0.0003, 0.0}, 1.0};
  EyeParams right{61.4, 1.003, -2.6, 1.8, {-0.105, 0.028, -0.0002, 0.0005, 0.0}, 0.96};
  RigParams rig;
  RobotParams robot;
  BallPhysicsParams ball;
  SensorParams sensor;

  /// First invalid field with its allowed range, or nullopt.
  std::optional<std::string> validate() const;
};

}  // namespace stereoball::simulator
