#pragma once
// Parameters of the simulated hardware: cameras, rig, robot base, ball physics, sensor.
// The scene itself (room, clutter, ball, script) is a Scenario (scenario.hpp).

#include <array>
#include <cstdint>

#include "common/params/field_table.hpp"
#include "common/util/result.hpp"
#include "simulator/core/vec3.hpp"

namespace stereoball::simulator {

/// One camera of the rig: intrinsics derived from the field of view, plus lens distortion.
struct EyeParams {
  double hfov_deg;                   ///< horizontal field of view of the pinhole part, degrees
  double fy_over_fx;                 ///< pixel aspect ratio fy / fx
  double cx_offset_px;               ///< principal point offset from the image centre, pixels
  double cy_offset_px;               ///< principal point offset from the image centre, pixels
  std::array<double, 5> distortion;  ///< OpenCV order k1 k2 p1 p2 k3, unitless
  double gain;                       ///< sensor gain of this eye relative to nominal
};

/// Stereo rig geometry and its mounting on the robot.
struct RigParams {
  double baseline_m;               ///< ideal distance between the optical centres, metres
  double height_m;                 ///< optical centre height above the floor, metres
  double forward_m;                ///< optical centre ahead of the robot centre, metres
  double tilt_rad;                 ///< downward pitch of the rig, radians (positive = down)
  Vec3d right_rotation_error_rad;  ///< right camera mis-rotation (x,y,z)
  Vec3d right_offset_error_m;      ///< right camera mis-placement, metres
  double rectify_alpha;            ///< cv::stereoRectify alpha: 0 = only valid pixels, 1 = all
};

/// Differential-drive base limits.
struct RobotParams {
  double max_linear_mps;            ///< |forward speed| limit, m/s
  double max_angular_radps;         ///< |yaw rate| limit, rad/s
  double max_linear_accel_mps2;     ///< |forward acceleration| limit, m/s^2
  double max_angular_accel_radps2;  ///< |yaw acceleration| limit, rad/s^2
  double max_linear_brake_mps2;     ///< |deceleration| limit while |speed| drops, m/s^2
  double max_angular_brake_radps2;  ///< |yaw deceleration| limit while |rate| drops
  int64_t command_timeout_ns;       ///< commands older than this stop the base, ns
  double radius_m;                  ///< footprint radius (walls, ball contact), metres
};

/// Ball physics.
struct BallPhysicsParams {
  double rolling_decel_mps2;  ///< constant deceleration of a rolling ball, m/s^2
  double restitution;         ///< fraction of normal speed kept after a bounce
  double physics_step_s;      ///< integration step of the world, seconds
};

/// Image sensor effects.
struct SensorParams {
  double noise_sigma_dn;      ///< Gaussian read noise, digital numbers (0..255 scale)
  int motion_blur_subframes;  ///< renders averaged per frame (1 = no motion blur)
  double shutter_s;           ///< exposure time spanned by the motion blur, seconds
};

/// Everything about the simulated hardware. Every value (of the sub-structs too) comes from
/// sim_fields(): key, default, range, unit, meaning.
struct SimParams {
  SimParams();           ///< every field at its default from sim_fields()
  int width_px;          ///< image width, pixels
  int height_px;         ///< image height, pixels
  double frame_rate_hz;  ///< stereo frames per simulated second
  EyeParams left;
  EyeParams right;
  RigParams rig;
  RobotParams robot;
  BallPhysicsParams ball;
  SensorParams sensor;

  /// Success, or the first field out of its range, naming key, range and unit.
  Status validate() const;
};

/// One row per parameter of config/simulator.yaml's hardware part: the defaults, validate(),
/// the file, the README table and `simulator --help-params` come from it.
const params::FieldTable<SimParams>& sim_fields();

}  // namespace stereoball::simulator
