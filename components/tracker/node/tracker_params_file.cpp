#include "tracker/node/tracker_params_file.hpp"

namespace stereoball::tracker {

Result<TrackerParams> read_tracker_params(params::ParamsFile& file) {
  constexpr std::int64_t kHour = 3'600'000'000'000;
  TrackerParams p;
  file.read("ssd_threshold", p.ssd_threshold, 1.0, 86'028'075.0);
  file.read("register_size", p.register_size, 3, 50);
  file.read("register_outliers_allowed", p.register_outliers_allowed, 0, 1);
  file.read("reacquire_positions", p.reacquire_positions, 2, 50);
  file.read("sigma_floor_m", p.sigma_floor_m, 0.0, 10.0);
  file.read("sigma_floor_fraction", p.sigma_floor_fraction, 0.0, 1.0);
  file.read("max_range_m", p.max_range_m, 0.1, 1000.0);
  file.read("max_static_spread_m", p.max_static_spread_m, 0.001, 10.0);
  file.read("line_tolerance_m", p.line_tolerance_m, 0.001, 10.0);
  file.read("max_ball_speed_mps", p.max_ball_speed_mps, 0.0, 100.0);
  file.read("jump_margin_m", p.jump_margin_m, 0.0, 10.0);
  file.read("register_max_age_ns", p.register_max_age_ns, std::int64_t{1}, kHour);
  file.read("lost_after_frames", p.lost_after_frames, 1, 100'000);
  file.read("lost_after_ns", p.lost_after_ns, std::int64_t{1}, kHour);
  file.read("velocity_window_ns", p.velocity_window_ns, std::int64_t{1}, kHour);
  file.read("side_center_band_fraction", p.side_center_band_fraction, 0.0, 0.99);
  file.read("side_min_speed_mps", p.side_min_speed_mps, 0.0, 100.0);
  if (auto e = p.validate()) file.fail(file.name() + ": " + *e);
  if (auto e = file.finish()) return Error{*e};
  return p;
}

Result<TrackerParams> load_tracker_params(const std::string& path) {
  auto file = params::ParamsFile::load(path);
  if (!file) return Error{file.error()};
  return read_tracker_params(*file);
}

}  // namespace stereoball::tracker
