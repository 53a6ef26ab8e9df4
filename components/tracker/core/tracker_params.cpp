#include "tracker/core/tracker_params.hpp"

namespace stereoball::tracker {
namespace {

using params::at;
using params::number;
using P = TrackerParams;
constexpr std::int64_t kHour = 3'600'000'000'000;

// A refilling register cannot need more positions than it holds.
Status reacquire_within_register(const P& p) {
  if (p.reacquire_positions <= p.register_size) return {};
  return Error{params::out_of_range("reacquire_positions", p.reacquire_positions,
                                    {2, static_cast<double>(p.register_size)}, "",
                                    "at most register_size")};
}

params::FieldTable<P> make_table() {
  return {{
              number("ssd_threshold", at(&P::ssd_threshold), 200'000.0, {1.0, 86'028'075.0}, "",
                     "block match when the SSD of 21x21 RGB blocks is below this (paper: 200,000)"),
              number("register_size", at(&P::register_size), 5, {3, 50}, "positions",
                     "positions in the shift register (paper: five)"),
              number("register_outliers_allowed", at(&P::register_outliers_allowed), 1, {0, 1},
                     "positions", "while tracking, judge the register without this many strays"),
              number("reacquire_positions", at(&P::reacquire_positions), 3, {2, 50}, "positions",
                     "after a loss, judge a refilling register from this many positions (at most "
                     "register_size; start-up: all)"),
              number("sigma_floor_m", at(&P::sigma_floor_m), 0.03, {0.0, 10.0}, "m",
                     "floor of the one-sigma radius around the mean"),
              number("sigma_floor_fraction", at(&P::sigma_floor_fraction), 0.02, {0.0, 1.0}, "",
                     "same floor as a fraction of the distance"),
              number("max_static_spread_m", at(&P::max_static_spread_m), 0.15, {0.001, 10.0}, "m",
                     "mean test only while the register spread is below this"),
              number("line_tolerance_m", at(&P::line_tolerance_m), 0.05, {0.001, 10.0}, "m",
                     "max distance to the best-fit line (and line RMS residual)"),
              number("max_range_m", at(&P::max_range_m), 20.0, {0.1, 1000.0}, "m",
                     "detections farther from the camera are refused (implausible or forged)"),
              number("max_ball_speed_mps", at(&P::max_ball_speed_mps), 5.0, {0.0, 100.0}, "m/s",
                     "max ball speed relative to the camera (jump gate)"),
              number("jump_margin_m", at(&P::jump_margin_m), 0.10, {0.0, 10.0}, "m",
                     "jump allowed on top of speed * dt"),
              number("register_max_age_ns", at(&P::register_max_age_ns), 1'000'000'000, {1, kHour},
                     "ns", "register cleared when its newest position is older"),
              number("lost_after_frames", at(&P::lost_after_frames), 8, {1, 100'000}, "frames",
                     "following -> searching after this many frames without acceptance"),
              number("lost_after_ns", at(&P::lost_after_ns), 400'000'000, {1, kHour}, "ns",
                     "... or after this long without acceptance"),
              number("velocity_window_ns", at(&P::velocity_window_ns), 500'000'000, {1, kHour},
                     "ns", "accepted positions within this window feed the velocity fit"),
              number("side_center_band_fraction", at(&P::side_center_band_fraction), 0.2,
                     {0.0, 0.99}, "",
                     "central band (of the half width) where motion, not the column, decides the "
                     "last-seen side"),
              number("side_min_speed_mps", at(&P::side_min_speed_mps), 0.1, {0.0, 100.0}, "m/s",
                     "min lateral speed for motion to decide the side"),
          },
          reacquire_within_register};
}

}  // namespace

SB_PARAMS_TABLE(TrackerParams, tracker_fields, make_table)

}  // namespace stereoball::tracker
