#include "simulator/io/randomize_file.hpp"

#include <vector>

namespace stereoball::simulator {
namespace {

// [lo, hi]; the bounds are RandomizeRanges::validate()'s to check, with the key named.
void read_range(params::ParamsFile& f, const std::string& key, Range& r) {
  std::vector<double> v{r.lo, r.hi};
  f.read(key, v, 2);
  if (v.size() == 2) r = {v[0], v[1]};
}

template <std::size_t N>
void read_weights(params::ParamsFile& f, const std::string& key, Weights<N>& w,
                  const std::array<const char*, N>& names) {
  for (std::size_t i = 0; i < N; ++i) f.read(key + "." + names[i], w[i], 0.0, 1000.0);
}

Result<RandomizeRanges> finish(params::ParamsFile& f) {
  RandomizeRanges r;
  read_randomize_ranges(f, r);
  if (auto st = f.finish(); !st) return Error{st.error()};
  if (auto e = r.validate(); !e) return Error{f.name() + ": " + e.error()};
  return r;
}

}  // namespace

void read_randomize_ranges(params::ParamsFile& f, RandomizeRanges& r) {
  f.read("duration_s", r.duration_s, 1.0, 600.0);
  read_range(f, "ball.diameter_m", r.ball_diameter_m);
  read_range(f, "ball.hue_deg", r.ball_hue_deg);
  read_range(f, "ball.saturation", r.ball_saturation);
  read_range(f, "ball.value", r.ball_value);
  read_range(f, "ball.second_value", r.ball_second_value);
  read_weights(f, "ball.pattern_weights", r.ball_pattern, kPatternNames);
  read_range(f, "ball.distance_m", r.ball_distance_m);
  read_range(f, "ball.bearing_deg", r.ball_bearing_deg);
  read_range(f, "ball.speed_mps", r.ball_speed_mps);
  read_weights(f, "floor.kind_weights", r.floor_kind, kFloorNames);
  f.read("floor.light_probability", r.floor_light_probability, 0.0, 1.0);
  read_range(f, "floor.light_value", r.floor_light_value);
  read_range(f, "floor.dark_value", r.floor_dark_value);
  read_range(f, "floor.saturation", r.floor_saturation);
  read_range(f, "floor.pattern_contrast", r.floor_pattern_contrast);
  read_range(f, "walls.value", r.wall_value);
  read_range(f, "walls.saturation", r.wall_saturation);
  read_range(f, "lighting.ambient", r.ambient);
  read_range(f, "lighting.sun", r.sun);
  read_range(f, "lighting.sun_azimuth_deg", r.sun_azimuth_deg);
  read_range(f, "lighting.sun_elevation_deg", r.sun_elevation_deg);
  read_range(f, "lighting.exposure", r.exposure);
  f.read("distractors.probability", r.distractor_probability, 0.0, 1.0);
  read_range(f, "distractors.boxes", r.boxes);
  read_range(f, "distractors.other_balls", r.other_balls);
  read_range(f, "distractors.wall_plates", r.wall_plates);
  read_range(f, "distractors.objects_on_boxes", r.objects_on_boxes);
  f.read("distractors.other_ball_min_hue_gap_deg", r.other_ball_min_hue_gap_deg, 0.0, 180.0);
  f.read("distractors.other_ball_min_size_ratio", r.other_ball_min_size_ratio, 1.0, 3.0);
  read_weights(f, "leave_view.kind_weights", r.leave_view, kLeaveNames);
  read_range(f, "leave_view.slow_turn_radps", r.slow_turn_radps);
  read_range(f, "leave_view.leave_speed_mps", r.leave_speed_mps);
  read_range(f, "leave_view.kick_speed_mps", r.kick_speed_mps);
  read_range(f, "leave_view.kick_time_s", r.kick_time_s);
}

Result<RandomizeRanges> load_randomize_ranges(const std::string& path) {
  auto f = params::ParamsFile::load(path);
  if (!f) return Error{f.error()};
  return finish(*f);
}

Result<RandomizeRanges> parse_randomize_ranges(const std::string& text, const std::string& name) {
  auto f = params::ParamsFile::parse(text, name);
  if (!f) return Error{f.error()};
  return finish(*f);
}

}  // namespace stereoball::simulator
