#pragma once
// Parameters of the tracker core (block matching, statistical verification,
// state machine). Defaults follow the paper where it gives a value.

#include <cstdint>
#include <optional>
#include <string>

namespace stereoball::tracker {

/// Tracker configuration; units are in the field names.
struct TrackerParams {
  /// Block match accepts when SSD < this (paper: 200,000 for 21x21 RGB blocks), unitless.
  double ssd_threshold = 200'000.0;
  /// Positions in the shift register (paper: five).
  int register_size = 5;
  /// While tracking, a register that is inconsistent because of this many stray
  /// positions (0 or 1) is still used without them. Start-up always needs all five.
  int register_outliers_allowed = 1;
  /// Addition: while tracking (never at start-up), a register refilling after a loss (its old
  /// positions expired) is judged once it holds this many positions, not register_size: each
  /// reacquisition then costs this many frames instead of five. In [2, register_size].
  int reacquire_positions = 3;
  /// Lower bound of the "one standard deviation" radius around the mean, metres.
  double sigma_floor_m = 0.03;
  /// Same lower bound as a fraction of the distance of the mean from the camera, unitless.
  double sigma_floor_fraction = 0.02;
  /// The mean test applies only while the register spread sqrt(trace(cov)) is below this, m.
  double max_static_spread_m = 0.15;
  /// Max distance of a position to the best-fit line, and max RMS line residual, metres.
  double line_tolerance_m = 0.05;
  /// Detections farther than this from the camera are refused before they reach the register
  /// (no stereo rig here measures a ball beyond it; a forged one must not drive the robot), m.
  double max_range_m = 20.0;
  /// Max plausible ball speed relative to the camera (gates position jumps), m/s.
  double max_ball_speed_mps = 5.0;
  /// Jump allowed on top of max_ball_speed_mps * dt (detector noise), metres.
  double jump_margin_m = 0.10;
  /// The register is cleared when its newest position is older than this, ns.
  std::int64_t register_max_age_ns = 1'000'000'000;
  /// FOLLOWING -> SEARCHING after this many frames without an accepted detection.
  int lost_after_frames = 8;
  /// FOLLOWING -> SEARCHING after this long without an accepted detection, ns.
  std::int64_t lost_after_ns = 400'000'000;
  /// Accepted positions within this window feed the velocity fit, ns.
  std::int64_t velocity_window_ns = 500'000'000;
  /// Central band of the image (fraction of the half width) where the motion, not the
  /// column, decides the last-seen side, unitless in [0, 1).
  double side_center_band_fraction = 0.2;
  /// Min lateral speed for the motion to decide the last-seen side, m/s.
  double side_min_speed_mps = 0.1;

  /// Empty when valid; otherwise names the bad field and its allowed range.
  std::optional<std::string> validate() const;
};

}  // namespace stereoball::tracker
