#pragma once
// Parameters of the motion controller core: following law, limits, search. Each field is
// declared once, in controller_fields() (key, default, range, unit, meaning).

#include <cstdint>

#include "common/params/field_table.hpp"
#include "common/util/result.hpp"

namespace stereoball::motion_controller {

/// Controller configuration; units are in the field names, the rest in controller_fields().
struct MotionControllerParams {
  MotionControllerParams();  ///< every field at its default from controller_fields()

  /// Negative = the left camera sits left of the robot's centreline (sim rig: -baseline/2).
  double camera_right_offset_m;
  double camera_forward_offset_m;
  double target_distance_m;
  double distance_gain_per_s;
  /// Ball to the right -> turn right = negative angular.
  double bearing_gain_per_s;
  double bearing_rate_feedforward;   ///< 0 = pure P control
  double distance_rate_feedforward;  ///< 0 = pure P control
  double distance_deadband_m;
  double bearing_deadband_rad;
  /// Turn first, then drive: forward speed scales with 1 - |bearing| / this.
  double slowdown_bearing_rad;
  double max_linear_mps;
  double max_reverse_mps;  ///< a positive number
  double max_angular_radps;
  double max_linear_accel_mps2;
  /// Slowing down may be harder than speeding up: the robot must stop short of a ball that
  /// turned toward it.
  double max_linear_brake_mps2;
  double max_angular_accel_radps2;
  double max_linear_jerk_mps3;
  double max_angular_jerk_radps3;
  double search_angular_radps;
  std::int64_t search_timeout_ns;
  bool search_left_when_unknown;
  std::int64_t stale_timeout_ns;
  std::int64_t position_hold_ns;
  std::int64_t max_step_ns;
  /// The track's bearing and range rates average the robot's own motion over the tracker's
  /// velocity window before the last accepted position, so that same average (not the
  /// present velocity) is removed from them.
  std::int64_t track_velocity_window_ns;
  /// Clock offset between hosts: a later capture stamp is rejected as lying in the future.
  std::int64_t future_stamp_tolerance_ns;

  /// Success, or the first field out of its range, naming key, range and unit.
  Status validate() const;
};

/// One row per parameter: the defaults, validate(), config/motion_controller.yaml, the README
/// table and `motion_controller --help-params` all come from it.
const params::FieldTable<MotionControllerParams>& controller_fields();

}  // namespace stereoball::motion_controller
