#pragma once
// Parameters of the tracker core (block matching, statistical verification, state machine).
// Each field is declared once, in tracker_fields() (key, default, range, unit, meaning): the
// defaults follow the paper where it gives a value.

#include <cstdint>

#include "common/params/field_table.hpp"
#include "common/util/result.hpp"

namespace stereoball::tracker {

/// Tracker configuration; units are in the field names, the rest in tracker_fields().
struct TrackerParams {
  TrackerParams();  ///< every field at its default from tracker_fields()

  double ssd_threshold;
  int register_size;
  /// While tracking, a register that is inconsistent because of this many stray positions is
  /// still used without them. Start-up always needs all five.
  int register_outliers_allowed;
  /// Addition: while tracking (never at start-up), a register refilling after a loss (its old
  /// positions expired) is judged once it holds this many positions, not register_size: each
  /// reacquisition then costs this many frames instead of five.
  int reacquire_positions;
  double sigma_floor_m;
  double sigma_floor_fraction;
  /// The mean test applies only while the register spread sqrt(trace(cov)) is below this.
  double max_static_spread_m;
  double line_tolerance_m;
  /// No stereo rig here measures a ball beyond this; a forged one must not drive the robot.
  double max_range_m;
  double max_ball_speed_mps;
  double jump_margin_m;
  std::int64_t register_max_age_ns;
  int lost_after_frames;
  std::int64_t lost_after_ns;
  std::int64_t velocity_window_ns;
  double side_center_band_fraction;
  double side_min_speed_mps;

  /// Success, or the first field out of its range: "key 'register_size': 2 is out of range [3,
  /// 50]".
  Status validate() const;
};

/// One row per parameter: the defaults, validate(), config/tracker.yaml, the README table and
/// `tracker --help-params` all come from it.
const params::FieldTable<TrackerParams>& tracker_fields();

}  // namespace stereoball::tracker
