#pragma once
// Randomised worlds: scenarios drawn from ranges of ball, floor, walls, lighting, distractors
// and ways for the ball to leave the view, each labelled with the categories the benchmarks
// report by. Pure: the same ranges, seed and index always give the same scene.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/util/result.hpp"
#include "simulator/core/scenario.hpp"

namespace stereoball::simulator {

/// A closed interval [lo, hi] a value is drawn uniformly from.
struct Range {
  double lo = 0.0, hi = 0.0;
};

/// Relative weights of the choices of one kind (all >= 0, at least one > 0).
template <std::size_t N>
using Weights = std::array<double, N>;

/// Ball patterns drawn: solid, panels, stripes, football (BallPattern order differs: names).
inline constexpr std::array<const char*, 4> kPatternNames{"solid", "panels", "stripes", "football"};
/// Floor kinds drawn.
inline constexpr std::array<const char*, 4> kFloorNames{"tiles", "planks", "carpet", "plain"};
/// Ways the ball leaves the view.
inline constexpr std::array<const char*, 4> kLeaveNames{"none", "slow_turn", "occluder", "kick"};

/// Every range a randomised scene is drawn from (config/randomize.yaml).
struct RandomizeRanges {
  double duration_s = 10.0;  ///< simulated seconds per scene
  // Ball: colour in HSV (hue degrees, saturation and value 0..1), pattern, size, start.
  Range ball_diameter_m{0.065, 0.24};
  Range ball_hue_deg{0.0, 360.0};
  Range ball_saturation{0.55, 0.95};
  Range ball_value{0.55, 0.95};
  Range ball_second_value{0.75, 1.0};  ///< the second colour of a two-colour ball: a light tone
  Weights<4> ball_pattern{1.0, 1.0, 1.0, 0.0};
  Range ball_distance_m{0.9, 2.5};  ///< from the robot at the start
  Range ball_bearing_deg{-15.0, 15.0};
  Range ball_speed_mps{0.0, 0.4};  ///< initial roll, any direction
  // Floor: kind, light or dark, colour.
  Weights<4> floor_kind{1.0, 1.0, 1.0, 1.0};
  double floor_light_probability = 0.5;
  Range floor_light_value{0.55, 0.85};
  Range floor_dark_value{0.12, 0.35};
  Range floor_saturation{0.0, 0.45};
  Range floor_pattern_contrast{0.1, 0.3};  ///< value difference of floor_b against floor_a
  // Walls.
  Range wall_value{0.45, 0.9};
  Range wall_saturation{0.0, 0.3};
  // Lighting.
  Range ambient{0.3, 0.65};
  Range sun{0.2, 0.9};
  Range sun_azimuth_deg{-180.0, 180.0};
  Range sun_elevation_deg{25.0, 80.0};
  Range exposure{0.8, 1.2};
  // Distractors (counts drawn as integers in [lo, hi]).
  Range boxes{1, 3};
  Range other_balls{0, 2};
  Range wall_plates{0, 2};
  Range objects_on_boxes{0, 1};
  double distractor_probability = 0.6;  ///< a scene has any distractor at all
  double other_ball_min_hue_gap_deg = 60.0;
  /// Other balls' diameter differs from the ball's by at least this factor (either way). The
  /// system is told only the ball's diameter: a ball of that size and another colour is, before
  /// its colour has been learnt, the ball, so a look-alike that close is no fair distractor.
  double other_ball_min_size_ratio = 1.3;
  // Leaving the view.
  Weights<4> leave_view{2.0, 1.0, 1.0, 1.0};
  Range slow_turn_radps{0.3, 0.6};  ///< the slow base's yaw-rate limit
  Range leave_speed_mps{0.6, 1.0};  ///< slow_turn / occluder: sideways roll
  Range kick_speed_mps{1.5, 2.5};
  Range kick_time_s{2.0, 4.0};

  /// Success, or the first invalid field (its YAML key) with the problem.
  Status validate() const;
};

/// What one scene is, in the benchmarks' categories.
struct SceneLabels {
  std::string ball_colour;  ///< hue name of the main colour: red, orange, yellow, ...
  std::string pattern;      ///< kPatternNames
  std::string floor;        ///< kFloorNames + "/light" or "/dark"
  std::string contrast;     ///< ball against floor, CIE76 delta E: low < 25 <= medium < 50 <= high
  std::string distractors;  ///< none, balls, plates, on_boxes, mixed
  std::string leave_view;   ///< kLeaveNames
  double contrast_delta_e = 0.0;
};

/// One randomised scene.
struct RandomScene {
  Scenario scenario;  ///< named "rand<seed>_<index>"
  SceneLabels labels;
  double ball_diameter_m = 0.0;
};

/// Scene index of a run with seed; depends only on (ranges, seed, index). ranges must be valid.
RandomScene draw_scene(const RandomizeRanges& ranges, std::uint64_t seed, int index);

/// Scenes 0..count-1.
std::vector<RandomScene> draw_scenes(const RandomizeRanges& ranges, std::uint64_t seed, int count);

/// Category names in report order, and a scene's value of each.
inline constexpr std::array<const char*, 6> kCategoryNames{
    "ball_colour", "pattern", "floor", "contrast", "distractors", "leave_view"};
const std::string& category_value(const SceneLabels& labels, std::size_t category);

/// Name of a hue in degrees (red, orange, yellow, green, cyan, blue, purple, pink).
const char* hue_name(double hue_deg);

/// CIE76 colour difference of two sRGB colours.
double delta_e(const Rgb& a, const Rgb& b);

/// sRGB of hue (degrees), saturation and value (0..1).
Rgb hsv(double hue_deg, double saturation, double value);

}  // namespace stereoball::simulator
