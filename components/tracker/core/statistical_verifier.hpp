#pragma once
// Statistical verification of paper section IV: a new position is accepted
// when it lies within one standard deviation of the register's mean or close
// to the register's best-fit line, provided the register itself describes a
// ball (a tight cluster or a clean line) and the jump is physically plausible.

#include <Eigen/Core>

#include <cstdint>
#include <string>

#include "tracker/core/position_register.hpp"
#include "tracker/core/tracker_params.hpp"

namespace stereoball::tracker {

/// Outcome of checking one position against the register.
struct StatsCheck {
  bool register_full = false;       ///< the register holds enough positions to judge
  bool steps_plausible = false;     ///< consecutive register positions obey the speed gate
  bool static_cluster = false;      ///< register spread <= max_static_spread_m
  bool clean_line = false;          ///< line residual <= line_tolerance_m and elongated
  bool jump_plausible = false;      ///< new position obeys the speed gate w.r.t. the newest
  bool by_mean = false;             ///< accepted by the mean test
  bool by_line = false;             ///< accepted by the line test
  bool accepted = false;            ///< by_mean || by_line
  double sigma_m = 0.0;             ///< register spread sqrt(trace(cov)), m
  double mean_radius_m = 0.0;       ///< radius used by the mean test max(sigma, floor), m
  double distance_to_mean_m = 0.0;  ///< |p - mean|, m
  double line_rms_m = 0.0;          ///< register RMS residual to its line, m
  double distance_to_line_m = 0.0;  ///< perpendicular distance of p to the line, m
  int outlier_left_out = -1;        ///< register index left out as a stray position (-1: none)
  std::string reason;               ///< short explanation for logs and the track message
};

/// Largest plausible displacement over dt_ns: jump_margin_m + max_ball_speed_mps * dt, metres.
double max_jump_m(const TrackerParams& params, std::int64_t dt_ns);

/// Checks position p (captured at stamp_ns) against the register; does not modify it. The
/// register speaks once it holds min_positions (0 = register_size, i.e. full). When the full
/// register is inconsistent and max_outliers is 1, each position is left out in turn and the
/// first consistent remainder that accepts p decides.
StatsCheck check_position(const PositionRegister& reg, const Eigen::Vector3d& p,
                          std::int64_t stamp_ns, const TrackerParams& params, int max_outliers = 0,
                          int min_positions = 0);

}  // namespace stereoball::tracker
