#include "simulator/core/randomize.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

namespace stereoball::simulator {
namespace {

constexpr int kScenes = 200;

bool within(double v, const Range& r) {
  return v >= r.lo - 1e-9 && v <= r.hi + 1e-9;
}

// HSV of an sRGB colour (hue degrees, saturation and value 0..1).
std::array<double, 3> to_hsv(const Rgb& c) {
  const double mx = std::max({c.r, c.g, c.b}), mn = std::min({c.r, c.g, c.b});
  double h = 0.0;
  if (mx > mn) {
    if (mx == c.r) {
      h = 60.0 * std::fmod((c.g - c.b) / (mx - mn) + 6.0, 6.0);
    } else if (mx == c.g) {
      h = 60.0 * ((c.b - c.r) / (mx - mn) + 2.0);
    } else {
      h = 60.0 * ((c.r - c.g) / (mx - mn) + 4.0);
    }
  }
  return {h, mx > 0 ? (mx - mn) / mx : 0.0, mx / 255.0};
}

TEST(Randomize, SameSeedGivesTheSameScenesAndAnotherSeedOthers) {
  // Given the default ranges
  const RandomizeRanges r;
  // When scenes are drawn twice with one seed and once with another
  const auto a = draw_scenes(r, 11, 20), b = draw_scenes(r, 11, 20), c = draw_scenes(r, 12, 20);
  // Then the same seed repeats every drawn value, and a scene does not depend on how many are drawn
  for (int i = 0; i < 20; ++i) {
    const Scenario& x = a[i].scenario;
    const Scenario& y = b[i].scenario;
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.seed, y.seed);
    EXPECT_EQ(x.ball->radius_m, y.ball->radius_m);
    EXPECT_EQ(x.ball->color_a.r, y.ball->color_a.r);
    EXPECT_EQ(x.ball->x_m, y.ball->x_m);
    EXPECT_EQ(x.room.floor_a.g, y.room.floor_a.g);
    EXPECT_EQ(x.boxes.size(), y.boxes.size());
    EXPECT_EQ(x.spheres.size(), y.spheres.size());
    EXPECT_EQ(x.lighting.front().sun, y.lighting.front().sun);
    EXPECT_EQ(a[i].labels.floor, b[i].labels.floor);
    EXPECT_EQ(draw_scene(r, 11, i).scenario.ball->vy_mps, x.ball->vy_mps);
  }
  int differ = 0;
  for (int i = 0; i < 20; ++i)
    differ += a[i].scenario.ball->radius_m != c[i].scenario.ball->radius_m;
  EXPECT_GE(differ, 18);
}

TEST(Randomize, EveryRangeIsRespectedAndEveryScenarioIsValid) {
  // Given narrowed ranges
  RandomizeRanges r;
  r.ball_diameter_m = {0.1, 0.12};
  r.ball_hue_deg = {100, 140};
  r.ball_saturation = {0.6, 0.7};
  r.ball_value = {0.7, 0.8};
  r.ball_distance_m = {1.0, 1.5};
  r.ball_bearing_deg = {-5, 5};
  r.floor_light_value = {0.6, 0.7};
  r.floor_dark_value = {0.2, 0.25};
  r.floor_saturation = {0.0, 0.2};
  r.ambient = {0.4, 0.5};
  r.sun = {0.3, 0.4};
  r.sun_elevation_deg = {30, 40};
  r.exposure = {0.9, 1.1};
  r.slow_turn_radps = {0.3, 0.4};
  r.kick_speed_mps = {1.5, 2.0};
  r.other_balls = {0, 2};
  // When many scenes are drawn
  for (const RandomScene& sc : draw_scenes(r, 3, kScenes)) {
    const Scenario& s = sc.scenario;
    SCOPED_TRACE(s.name);
    // Then each one is a valid scenario within every range
    ASSERT_TRUE(s.validate().ok()) << s.validate().error();
    ASSERT_TRUE(s.ball.has_value());
    EXPECT_TRUE(within(2.0 * s.ball->radius_m, r.ball_diameter_m));
    EXPECT_DOUBLE_EQ(sc.ball_diameter_m, 2.0 * s.ball->radius_m);
    const auto hsv_a = to_hsv(s.ball->color_a);
    EXPECT_TRUE(within(hsv_a[0], {r.ball_hue_deg.lo - 0.5, r.ball_hue_deg.hi + 0.5}));
    EXPECT_TRUE(within(hsv_a[1], {r.ball_saturation.lo - 0.01, r.ball_saturation.hi + 0.01}));
    EXPECT_TRUE(within(hsv_a[2], {r.ball_value.lo - 0.01, r.ball_value.hi + 0.01}));
    EXPECT_TRUE(within(std::hypot(s.ball->x_m - 0.1, s.ball->y_m), r.ball_distance_m));
    EXPECT_TRUE(
        within(std::atan2(s.ball->y_m, s.ball->x_m - 0.1) * 180 / M_PI, r.ball_bearing_deg));
    const double floor_v = to_hsv(s.room.floor_a)[2];
    EXPECT_TRUE(within(floor_v, {r.floor_dark_value.lo - 0.01, r.floor_dark_value.hi + 0.01}) ||
                within(floor_v, {r.floor_light_value.lo - 0.01, r.floor_light_value.hi + 0.01}));
    EXPECT_LE(to_hsv(s.room.floor_a)[1], r.floor_saturation.hi + 0.01);
    const LightKey& l = s.lighting.front();
    EXPECT_TRUE(within(l.ambient, r.ambient));
    EXPECT_TRUE(within(l.sun, r.sun));
    EXPECT_TRUE(within(l.exposure, r.exposure));
    EXPECT_TRUE(within(s.sun_elevation_rad * 180 / M_PI, r.sun_elevation_deg));
    if (s.robot_max_angular_radps) {
      EXPECT_EQ(sc.labels.leave_view, "slow_turn");
      EXPECT_TRUE(within(*s.robot_max_angular_radps, r.slow_turn_radps));
    }
    if (sc.labels.leave_view == "kick") {
      ASSERT_EQ(s.kicks.size(), 1u);
      EXPECT_TRUE(within(std::hypot(s.kicks[0].vx_mps, s.kicks[0].vy_mps), r.kick_speed_mps));
    }
    int floor_balls = 0;
    for (const SphereSpec& sp : s.spheres) {
      EXPECT_TRUE(within(2.0 * sp.radius_m, {0.0, r.ball_diameter_m.hi}));
      if (std::abs(sp.center_m.z - sp.radius_m) < 1e-9) {
        ++floor_balls;
        // Other balls on the floor differ in hue from the ball by the configured gap, and in
        // size by the configured factor
        const double gap = std::abs(to_hsv(sp.color)[0] - hsv_a[0]);
        EXPECT_GE(std::min(gap, 360.0 - gap), r.other_ball_min_hue_gap_deg - 1.0);
        const double ratio = sp.radius_m / s.ball->radius_m;
        EXPECT_GE(std::max(ratio, 1.0 / ratio), r.other_ball_min_size_ratio - 1e-9);
      }
    }
    EXPECT_LE(floor_balls, static_cast<int>(r.other_balls.hi));
  }
}

TEST(Randomize, EveryKindOfEveryCategoryIsDrawn) {
  // Given the default ranges, when many scenes are drawn
  std::set<std::string> seen[kCategoryNames.size()];
  for (const RandomScene& sc : draw_scenes(RandomizeRanges{}, 5, kScenes))
    for (std::size_t c = 0; c < kCategoryNames.size(); ++c)
      seen[c].insert(category_value(sc.labels, c));
  // Then each pattern, floor kind x tone, and leave kind occurs, and distractors vary
  EXPECT_EQ(seen[1], (std::set<std::string>{"solid", "panels", "stripes"}));
  EXPECT_EQ(seen[2].size(), 8u);
  EXPECT_EQ(seen[5], (std::set<std::string>{"none", "slow_turn", "occluder", "kick"}));
  EXPECT_GE(seen[4].size(), 4u);
  EXPECT_GE(seen[0].size(), 6u);
  EXPECT_EQ(seen[3], (std::set<std::string>{"low", "medium", "high"}));
}

TEST(Randomize, ZeroWeightKindsAreNeverDrawn) {
  // Given only striped balls on carpet and no leaving
  RandomizeRanges r;
  r.ball_pattern = {0, 0, 1, 0};
  r.floor_kind = {0, 0, 1, 0};
  r.leave_view = {1, 0, 0, 0};
  r.distractor_probability = 0.0;
  for (const RandomScene& sc : draw_scenes(r, 9, 50)) {
    EXPECT_EQ(sc.scenario.ball->pattern, BallPattern::kStripes);
    EXPECT_EQ(sc.scenario.room.floor_pattern, FloorPattern::kCarpet);
    EXPECT_TRUE(sc.scenario.kicks.empty());
    EXPECT_EQ(sc.labels.distractors, "none");
    EXPECT_TRUE(sc.scenario.spheres.empty());
  }
}

TEST(Randomize, ValidateNamesTheBadKey) {
  RandomizeRanges r;
  r.ball_diameter_m = {0.3, 0.2};
  ASSERT_FALSE(r.validate().ok());
  EXPECT_NE(r.validate().error().find("ball.diameter_m"), std::string::npos)
      << r.validate().error();
  r = {};
  r.floor_kind = {0, 0, 0, 0};
  ASSERT_FALSE(r.validate().ok());
  EXPECT_NE(r.validate().error().find("floor.kind_weights"), std::string::npos);
  r = {};
  r.sun_elevation_deg = {10, 95};
  ASSERT_FALSE(r.validate().ok());
  EXPECT_NE(r.validate().error().find("lighting.sun_elevation_deg"), std::string::npos);
}

TEST(Randomize, HueNamesAndColourDifference) {
  EXPECT_STREQ(hue_name(0), "red");
  EXPECT_STREQ(hue_name(359), "red");
  EXPECT_STREQ(hue_name(120), "green");
  EXPECT_STREQ(hue_name(230), "blue");
  EXPECT_NEAR(delta_e({255, 255, 255}, {0, 0, 0}), 100.0, 0.1);
  EXPECT_NEAR(delta_e({10, 200, 30}, {10, 200, 30}), 0.0, 1e-9);
  const Rgb red = hsv(0, 1, 1);
  EXPECT_NEAR(red.r, 255, 1e-9);
  EXPECT_NEAR(red.g, 0, 1e-9);
}

}  // namespace
}  // namespace stereoball::simulator
