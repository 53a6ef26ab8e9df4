#include "tracker/core/tracker_params.hpp"

#include <cmath>
#include <sstream>

namespace stereoball::tracker {
namespace {

template <typename T>
std::optional<std::string> check_range(const char* name, T value, T lo, T hi, const char* unit) {
  if (!(value >= lo && value <= hi)) {  // written so NaN fails too
    std::ostringstream os;
    os << name << " = " << value << " is out of range [" << lo << ", " << hi << "]" << unit;
    return os.str();
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> TrackerParams::validate() const {
  constexpr std::int64_t kHour = 3'600'000'000'000;
  for (const auto& r : {
           check_range("ssd_threshold", ssd_threshold, 1.0, 86'028'075.0, ""),
           check_range("register_size", register_size, 3, 50, ""),
           check_range("register_outliers_allowed", register_outliers_allowed, 0, 1, ""),
           check_range("reacquire_positions", reacquire_positions, 2, register_size,
                       " (at most register_size)"),
           check_range("sigma_floor_m", sigma_floor_m, 0.0, 10.0, " m"),
           check_range("sigma_floor_fraction", sigma_floor_fraction, 0.0, 1.0, ""),
           check_range("max_static_spread_m", max_static_spread_m, 0.001, 10.0, " m"),
           check_range("line_tolerance_m", line_tolerance_m, 0.001, 10.0, " m"),
           check_range("max_range_m", max_range_m, 0.1, 1000.0, " m"),
           check_range("max_ball_speed_mps", max_ball_speed_mps, 0.0, 100.0, " m/s"),
           check_range("jump_margin_m", jump_margin_m, 0.0, 10.0, " m"),
           check_range<std::int64_t>("register_max_age_ns", register_max_age_ns, 1, kHour, " ns"),
           check_range("lost_after_frames", lost_after_frames, 1, 100'000, ""),
           check_range<std::int64_t>("lost_after_ns", lost_after_ns, 1, kHour, " ns"),
           check_range<std::int64_t>("velocity_window_ns", velocity_window_ns, 1, kHour, " ns"),
           check_range("side_center_band_fraction", side_center_band_fraction, 0.0, 0.99, ""),
           check_range("side_min_speed_mps", side_min_speed_mps, 0.0, 100.0, " m/s"),
       }) {
    if (r) return r;
  }
  return std::nullopt;
}

}  // namespace stereoball::tracker
