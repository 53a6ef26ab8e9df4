#include "simulator/core/randomize.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace stereoball::simulator {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kRollingDecelMps2 = 0.12;  // config/simulator.yaml ball.rolling_decel_mps2
constexpr int kPlacementTries = 40;

// SplitMix64: the same numbers on every platform (std distributions are not portable).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  double unit() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }
  double uniform(const Range& r) { return r.lo + (r.hi - r.lo) * unit(); }
  double uniform(double lo, double hi) { return uniform(Range{lo, hi}); }
  int integer(const Range& r) {
    const int lo = static_cast<int>(std::lround(r.lo)), hi = static_cast<int>(std::lround(r.hi));
    return lo + static_cast<int>(next() % static_cast<std::uint64_t>(hi - lo + 1));
  }
  bool chance(double p) { return unit() < p; }
  template <std::size_t N>
  std::size_t pick(const Weights<N>& w) {
    double total = 0.0;
    for (double x : w) total += x;
    double u = unit() * total;
    for (std::size_t i = 0; i < N; ++i) {
      if (u < w[i]) return i;
      u -= w[i];
    }
    for (std::size_t i = N; i-- > 0;)
      if (w[i] > 0.0) return i;
    return 0;
  }

 private:
  std::uint64_t state_;
};

Status check_range(const std::string& key, const Range& r, double lo, double hi) {
  std::ostringstream s;
  if (!(std::isfinite(r.lo) && std::isfinite(r.hi) && r.lo >= lo && r.hi <= hi)) {
    s << "[" << r.lo << ", " << r.hi << "] is not within [" << lo << ", " << hi << "]";
  } else if (r.lo > r.hi) {
    s << "lower end " << r.lo << " is above upper end " << r.hi;
  } else {
    return {};
  }
  return Error{key + ": " + s.str()};
}

template <std::size_t N>
Status check_weights(const std::string& key, const Weights<N>& w,
                     const std::array<const char*, N>& names) {
  double total = 0.0;
  for (std::size_t i = 0; i < N; ++i) {
    if (!(std::isfinite(w[i]) && w[i] >= 0.0 && w[i] <= 1000.0))
      return Error{key + "." + names[i] + ": weight must be in [0, 1000]"};
    total += w[i];
  }
  if (!(total > 0.0)) return Error{key + ": at least one weight must be positive"};
  return {};
}

Status check_probability(const std::string& key, double p) {
  if (std::isfinite(p) && p >= 0.0 && p <= 1.0) return {};
  return Error{key + ": probability must be in [0, 1]"};
}

Rgb hsv_wrapped(double hue_deg, double s, double v) {
  return hsv(std::fmod(std::fmod(hue_deg, 360.0) + 360.0, 360.0), std::clamp(s, 0.0, 1.0),
             std::clamp(v, 0.0, 1.0));
}

double lab_f(double t) {
  return t > 0.008856 ? std::cbrt(t) : 7.787 * t + 16.0 / 116.0;
}

std::array<double, 3> to_lab(const Rgb& c) {
  auto lin = [](double v) {
    v /= 255.0;
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
  };
  const double r = lin(c.r), g = lin(c.g), b = lin(c.b);
  const double x = (0.4124 * r + 0.3576 * g + 0.1805 * b) / 0.95047;
  const double y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
  const double z = (0.0193 * r + 0.1192 * g + 0.9505 * b) / 1.08883;
  const double fx = lab_f(x), fy = lab_f(y), fz = lab_f(z);
  return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

Rgb average(const Rgb& a, const Rgb& b) {
  return {0.5 * (a.r + b.r), 0.5 * (a.g + b.g), 0.5 * (a.b + b.b)};
}

// A point on the floor inside the room, clear of the robot's start and of every keep-away disc.
struct Keepout {
  double x_m, y_m, radius_m;
};
std::optional<std::pair<double, double>> free_spot(Rng& rng, const RoomSpec& room, double margin_m,
                                                   const std::vector<Keepout>& keepouts) {
  for (int i = 0; i < kPlacementTries; ++i) {
    const double x = rng.uniform(0.6, room.x_max_m - margin_m);
    const double y = rng.uniform(room.y_min_m + margin_m, room.y_max_m - margin_m);
    bool clear = true;
    for (const Keepout& k : keepouts)
      clear = clear && std::hypot(x - k.x_m, y - k.y_m) > k.radius_m + margin_m;
    if (clear) return std::pair{x, y};
  }
  return std::nullopt;
}

void draw_room(Rng& rng, const RandomizeRanges& r, Scenario& s, SceneLabels& labels) {
  const std::size_t kind = rng.pick(r.floor_kind);
  const bool light = rng.chance(r.floor_light_probability);
  const double hue = rng.uniform(0.0, 360.0), sat = rng.uniform(r.floor_saturation);
  const double value = rng.uniform(light ? r.floor_light_value : r.floor_dark_value);
  // The pattern's second tone goes toward the middle grey, so it stays within the range.
  const double step = rng.uniform(r.floor_pattern_contrast) * (light ? -1.0 : 1.0);
  RoomSpec& room = s.room;
  room.floor_a = hsv_wrapped(hue, sat, value);
  room.floor_b = hsv_wrapped(hue, sat, value + step);
  room.grout = hsv_wrapped(hue, 0.5 * sat, value * (light ? 0.55 : 0.6));
  room.plain = kind == 3;
  room.floor_pattern = kind == 1   ? FloorPattern::kPlanks
                       : kind == 2 ? FloorPattern::kCarpet
                                   : FloorPattern::kTiles;
  room.tile_m = kind == 1 ? 0.6 : rng.uniform(0.3, 0.6);
  const double wall_hue = rng.uniform(0.0, 360.0), wall_sat = rng.uniform(r.wall_saturation);
  const double wall_value = rng.uniform(r.wall_value);
  room.wall = hsv_wrapped(wall_hue, wall_sat, wall_value);
  room.baseboard = hsv_wrapped(wall_hue, wall_sat, 0.5 * wall_value);
  labels.floor = std::string(kFloorNames[kind]) + (light ? "/light" : "/dark");
}

void draw_lighting(Rng& rng, const RandomizeRanges& r, Scenario& s) {
  s.sun_azimuth_rad = rng.uniform(r.sun_azimuth_deg) * kDeg;
  s.sun_elevation_rad = rng.uniform(r.sun_elevation_deg) * kDeg;
  s.lighting = {LightKey{0.0, rng.uniform(r.ambient), rng.uniform(r.sun), rng.uniform(r.exposure)}};
}

struct DrawnBall {
  double diameter_m, hue_deg;
};

DrawnBall draw_ball(Rng& rng, const RandomizeRanges& r, Scenario& s, SceneLabels& labels) {
  BallSpec b;
  const double diameter = rng.uniform(r.ball_diameter_m);
  b.radius_m = 0.5 * diameter;
  const double hue = rng.uniform(r.ball_hue_deg);
  b.color_a = hsv_wrapped(hue, rng.uniform(r.ball_saturation), rng.uniform(r.ball_value));
  const std::size_t pattern = rng.pick(r.ball_pattern);
  b.pattern = pattern == 0   ? BallPattern::kSolid
              : pattern == 1 ? BallPattern::kPanels
              : pattern == 2 ? BallPattern::kStripes
                             : BallPattern::kFootball;
  // The second colour: a light tone of a far hue, from nearly white to saturated.
  b.color_b = pattern == 0 ? b.color_a
                           : hsv_wrapped(hue + rng.uniform(120.0, 240.0), rng.uniform(0.0, 0.8),
                                         rng.uniform(r.ball_second_value));
  const double distance = rng.uniform(r.ball_distance_m);
  const double bearing = rng.uniform(r.ball_bearing_deg) * kDeg;
  b.x_m = 0.1 + distance * std::cos(bearing);
  b.y_m = distance * std::sin(bearing);
  const double speed = rng.uniform(r.ball_speed_mps), heading = rng.uniform(-kPi, kPi);
  b.vx_mps = speed * std::cos(heading);
  b.vy_mps = speed * std::sin(heading);
  s.ball = b;
  labels.ball_colour = hue_name(std::fmod(hue + 360.0, 360.0));
  labels.pattern = kPatternNames[pattern];
  labels.contrast_delta_e = delta_e(b.color_a, average(s.room.floor_a, s.room.floor_b));
  labels.contrast = labels.contrast_delta_e < 25.0   ? "low"
                    : labels.contrast_delta_e < 50.0 ? "medium"
                                                     : "high";
  return {diameter, hue};
}

void draw_leave_view(Rng& rng, const RandomizeRanges& r, Scenario& s, SceneLabels& labels) {
  const std::size_t kind = rng.pick(r.leave_view);
  labels.leave_view = kLeaveNames[kind];
  if (kind == 0) return;
  BallSpec& b = *s.ball;
  const double side = rng.chance(0.5) ? 1.0 : -1.0;  // +1: leaves to the robot's left
  // Sideways: across the line of sight from the robot to the ball.
  const double d = std::hypot(b.x_m, b.y_m);
  const double ax = -b.y_m / d * side, ay = b.x_m / d * side;
  if (kind == 3) {
    const double v = rng.uniform(r.kick_speed_mps);
    s.kicks.push_back({std::min(rng.uniform(r.kick_time_s), s.duration_s), v * ax, v * ay});
    return;
  }
  const double v = rng.uniform(r.leave_speed_mps);
  b.vx_mps = v * ax;
  b.vy_mps = v * ay;
  if (kind == 1) {
    s.robot_max_angular_radps = rng.uniform(r.slow_turn_radps);
    return;
  }
  // Occluder: a box halfway to where the ball comes to rest, tall enough to hide it; the ball
  // is kicked back out a few seconds later.
  const double roll_m = std::min(v * v / (2.0 * kRollingDecelMps2), 1.5);
  const double rest_x = b.x_m + roll_m * ax, rest_y = b.y_m + roll_m * ay;
  BoxSpec box;
  box.x_m = 0.5 * (rest_x + 0.1);
  box.y_m = std::clamp(0.5 * rest_y, s.room.y_min_m + 0.4, s.room.y_max_m - 0.4);
  box.size_x_m = 0.3;
  box.size_y_m = rng.uniform(0.5, 0.8);
  box.size_z_m = rng.uniform(0.5, 0.8);
  box.color = hsv_wrapped(rng.uniform(0.0, 360.0), rng.uniform(0.0, 0.6), rng.uniform(0.2, 0.8));
  s.boxes.push_back(box);
  const double back_s = std::min(rng.uniform(r.kick_time_s) + 3.0, s.duration_s);
  s.kicks.push_back({back_s, -0.6 * ax, -0.6 * ay});
}

Rgb other_colour(Rng& rng, const RandomizeRanges& r, double ball_hue) {
  const double gap = r.other_ball_min_hue_gap_deg;
  return hsv_wrapped(ball_hue + rng.uniform(gap, 360.0 - gap), rng.uniform(r.ball_saturation),
                     rng.uniform(r.ball_value));
}

// A drawn diameter moved out of (ball / ratio, ball * ratio), to the nearer side that stays
// within the range's top (no extra draw, so the scene's other draws are unchanged).
double other_ball_diameter(double drawn_m, double ball_m, const RandomizeRanges& r) {
  const double k = r.other_ball_min_size_ratio;
  if (drawn_m <= ball_m / k || drawn_m >= ball_m * k) return drawn_m;
  const bool larger_fits = ball_m * k <= r.ball_diameter_m.hi;
  return drawn_m >= ball_m && larger_fits ? ball_m * k : ball_m / k;
}

PlateSpec wall_plate(Rng& rng, const RoomSpec& room) {
  PlateSpec p;
  const int wall = static_cast<int>(rng.next() % 3);  // far wall, right wall, left wall
  const double z = rng.uniform(0.2, 1.6);
  if (wall == 0) {
    p.center_m = {room.x_max_m - 0.01, rng.uniform(room.y_min_m + 0.3, room.y_max_m - 0.3), z};
    p.normal = {-1.0, 0.0, 0.0};
  } else {
    const double y = wall == 1 ? room.y_min_m + 0.01 : room.y_max_m - 0.01;
    p.center_m = {rng.uniform(1.0, room.x_max_m - 0.3), y, z};
    p.normal = {0.0, wall == 1 ? 1.0 : -1.0, 0.0};
  }
  p.radius_m = rng.uniform(0.05, 0.2);
  p.rim_m = rng.uniform(0.0, 0.3) * p.radius_m;
  p.color = hsv_wrapped(rng.uniform(0.0, 360.0), rng.uniform(0.0, 0.9), rng.uniform(0.3, 0.95));
  p.rim_color = hsv_wrapped(rng.uniform(0.0, 360.0), rng.uniform(0.0, 0.5), rng.uniform(0.3, 1.0));
  return p;
}

BoxSpec clutter_box(Rng& rng, double x, double y) {
  BoxSpec box;
  box.x_m = x;
  box.y_m = y;
  box.size_x_m = rng.uniform(0.25, 0.7);
  box.size_y_m = rng.uniform(0.25, 0.7);
  box.size_z_m = rng.uniform(0.2, 0.8);
  box.color = hsv_wrapped(rng.uniform(0.0, 360.0), rng.uniform(0.0, 0.6), rng.uniform(0.2, 0.8));
  return box;
}

void draw_clutter(Rng& rng, const RandomizeRanges& r, double ball_hue, Scenario& s,
                  SceneLabels& labels) {
  const BallSpec& b = *s.ball;
  std::vector<Keepout> keep{{0.0, 0.0, 0.8}, {b.x_m, b.y_m, 0.6}};
  for (const BoxSpec& box : s.boxes) keep.push_back({box.x_m, box.y_m, 0.5});
  for (int i = rng.integer(r.boxes); i > 0; --i) {
    if (auto spot = free_spot(rng, s.room, 0.4, keep)) {
      s.boxes.push_back(clutter_box(rng, spot->first, spot->second));
      keep.push_back({spot->first, spot->second, 0.5});
    }
  }
  int balls = 0, plates = 0, on_boxes = 0;
  if (rng.chance(r.distractor_probability)) {
    balls = rng.integer(r.other_balls);
    plates = rng.integer(r.wall_plates);
    on_boxes = rng.integer(r.objects_on_boxes);
    if (balls + plates + on_boxes == 0) {
      const int which = static_cast<int>(rng.next() % 3);
      (which == 0 ? balls : which == 1 ? plates : on_boxes) = 1;
    }
  }
  int placed_balls = 0, placed_on_boxes = 0;
  for (int i = 0; i < balls; ++i) {
    const double radius =
        0.5 * other_ball_diameter(rng.uniform(r.ball_diameter_m), 2.0 * b.radius_m, r);
    if (auto spot = free_spot(rng, s.room, 0.3 + radius, keep)) {
      s.spheres.push_back(
          {{spot->first, spot->second, radius}, radius, other_colour(rng, r, ball_hue)});
      keep.push_back({spot->first, spot->second, radius + 0.2});
      ++placed_balls;
    }
  }
  for (int i = 0; i < plates; ++i) s.plates.push_back(wall_plate(rng, s.room));
  for (int i = 0; i < on_boxes; ++i) {
    if (auto spot = free_spot(rng, s.room, 0.4, keep)) {
      BoxSpec box = clutter_box(rng, spot->first, spot->second);
      const double radius = std::min(0.5 * rng.uniform(r.ball_diameter_m),
                                     0.45 * std::min(box.size_x_m, box.size_y_m));
      s.boxes.push_back(box);
      // Any colour, the ball's own included: the floor check, not the colour, must reject it.
      s.spheres.push_back({{box.x_m, box.y_m, box.size_z_m + radius},
                           radius,
                           hsv_wrapped(rng.uniform(0.0, 360.0), rng.uniform(r.ball_saturation),
                                       rng.uniform(r.ball_value))});
      keep.push_back({spot->first, spot->second, 0.5});
      ++placed_on_boxes;
    }
  }
  const int kinds = (placed_balls > 0) + (plates > 0) + (placed_on_boxes > 0);
  labels.distractors = kinds == 0         ? "none"
                       : kinds > 1        ? "mixed"
                       : placed_balls > 0 ? "balls"
                       : plates > 0       ? "plates"
                                          : "on_boxes";
}

std::uint64_t scene_seed(std::uint64_t seed, int index) {
  Rng mix(seed * 0x9e3779b97f4a7c15ull + static_cast<std::uint64_t>(index) + 1);
  mix.next();
  return mix.next();
}

}  // namespace

Status RandomizeRanges::validate() const {
  if (!(std::isfinite(duration_s) && duration_s >= 1.0 && duration_s <= 600.0))
    return Error{"duration_s: must be in [1, 600] s"};
  const std::pair<const char*, std::pair<const Range*, std::pair<double, double>>> ranges[] = {
      {"ball.diameter_m", {&ball_diameter_m, {0.02, 1.0}}},
      {"ball.hue_deg", {&ball_hue_deg, {-360.0, 720.0}}},
      {"ball.saturation", {&ball_saturation, {0.0, 1.0}}},
      {"ball.value", {&ball_value, {0.05, 1.0}}},
      {"ball.second_value", {&ball_second_value, {0.05, 1.0}}},
      {"ball.distance_m", {&ball_distance_m, {0.5, 4.0}}},
      {"ball.bearing_deg", {&ball_bearing_deg, {-25.0, 25.0}}},
      {"ball.speed_mps", {&ball_speed_mps, {0.0, 3.0}}},
      {"floor.light_value", {&floor_light_value, {0.0, 1.0}}},
      {"floor.dark_value", {&floor_dark_value, {0.0, 1.0}}},
      {"floor.saturation", {&floor_saturation, {0.0, 1.0}}},
      {"floor.pattern_contrast", {&floor_pattern_contrast, {0.0, 0.5}}},
      {"walls.value", {&wall_value, {0.0, 1.0}}},
      {"walls.saturation", {&wall_saturation, {0.0, 1.0}}},
      {"lighting.ambient", {&ambient, {0.0, 2.0}}},
      {"lighting.sun", {&sun, {0.0, 2.0}}},
      {"lighting.sun_azimuth_deg", {&sun_azimuth_deg, {-360.0, 360.0}}},
      {"lighting.sun_elevation_deg", {&sun_elevation_deg, {6.0, 89.0}}},
      {"lighting.exposure", {&exposure, {0.05, 5.0}}},
      {"distractors.boxes", {&boxes, {0.0, 10.0}}},
      {"distractors.other_balls", {&other_balls, {0.0, 10.0}}},
      {"distractors.wall_plates", {&wall_plates, {0.0, 10.0}}},
      {"distractors.objects_on_boxes", {&objects_on_boxes, {0.0, 10.0}}},
      {"leave_view.slow_turn_radps", {&slow_turn_radps, {0.05, 2.0}}},
      {"leave_view.leave_speed_mps", {&leave_speed_mps, {0.1, 3.0}}},
      {"leave_view.kick_speed_mps", {&kick_speed_mps, {0.1, 5.0}}},
      {"leave_view.kick_time_s", {&kick_time_s, {0.0, duration_s}}},
  };
  for (const auto& [key, spec] : ranges) {
    if (auto e = check_range(key, *spec.first, spec.second.first, spec.second.second); !e) return e;
  }
  if (auto e = check_weights("ball.pattern_weights", ball_pattern, kPatternNames); !e) return e;
  if (auto e = check_weights("floor.kind_weights", floor_kind, kFloorNames); !e) return e;
  if (auto e = check_weights("leave_view.kind_weights", leave_view, kLeaveNames); !e) return e;
  if (auto e = check_probability("floor.light_probability", floor_light_probability); !e) return e;
  if (auto e = check_probability("distractors.probability", distractor_probability); !e) return e;
  if (!(other_ball_min_hue_gap_deg >= 0.0 && other_ball_min_hue_gap_deg <= 180.0))
    return Error{"distractors.other_ball_min_hue_gap_deg: must be in [0, 180]"};
  if (!(other_ball_min_size_ratio >= 1.0 && other_ball_min_size_ratio <= 3.0))
    return Error{"distractors.other_ball_min_size_ratio: must be in [1, 3]"};
  return {};
}

RandomScene draw_scene(const RandomizeRanges& r, std::uint64_t seed, int index) {
  Rng rng(scene_seed(seed, index));
  RandomScene out;
  Scenario& s = out.scenario;
  s.name = "rand" + std::to_string(seed) + "_" + std::to_string(index);
  s.seed = rng.next() % 1000000000ull + 1;
  s.duration_s = r.duration_s;
  draw_room(rng, r, s, out.labels);
  draw_lighting(rng, r, s);
  const DrawnBall ball = draw_ball(rng, r, s, out.labels);
  out.ball_diameter_m = ball.diameter_m;
  draw_leave_view(rng, r, s, out.labels);
  draw_clutter(rng, r, ball.hue_deg, s, out.labels);
  return out;
}

std::vector<RandomScene> draw_scenes(const RandomizeRanges& ranges, std::uint64_t seed, int count) {
  std::vector<RandomScene> out;
  for (int i = 0; i < count; ++i) out.push_back(draw_scene(ranges, seed, i));
  return out;
}

const std::string& category_value(const SceneLabels& l, std::size_t category) {
  const std::string* values[] = {&l.ball_colour, &l.pattern,     &l.floor,
                                 &l.contrast,    &l.distractors, &l.leave_view};
  return *values[std::min<std::size_t>(category, 5)];
}

const char* hue_name(double h) {
  h = std::fmod(std::fmod(h, 360.0) + 360.0, 360.0);
  if (h < 15.0 || h >= 345.0) return "red";
  if (h < 45.0) return "orange";
  if (h < 70.0) return "yellow";
  if (h < 160.0) return "green";
  if (h < 200.0) return "cyan";
  if (h < 255.0) return "blue";
  if (h < 295.0) return "purple";
  return "pink";
}

double delta_e(const Rgb& a, const Rgb& b) {
  const auto la = to_lab(a), lb = to_lab(b);
  return std::sqrt((la[0] - lb[0]) * (la[0] - lb[0]) + (la[1] - lb[1]) * (la[1] - lb[1]) +
                   (la[2] - lb[2]) * (la[2] - lb[2]));
}

Rgb hsv(double h, double s, double v) {
  const double c = v * s, hp = h / 60.0;
  const double x = c * (1.0 - std::abs(std::fmod(hp, 2.0) - 1.0));
  double r = 0, g = 0, b = 0;
  if (hp < 1)
    r = c, g = x;
  else if (hp < 2)
    r = x, g = c;
  else if (hp < 3)
    g = c, b = x;
  else if (hp < 4)
    g = x, b = c;
  else if (hp < 5)
    r = x, b = c;
  else
    r = c, b = x;
  const double m = v - c;
  return {255.0 * (r + m), 255.0 * (g + m), 255.0 * (b + m)};
}

}  // namespace stereoball::simulator
