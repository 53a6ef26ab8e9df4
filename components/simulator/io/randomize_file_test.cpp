#include "simulator/io/randomize_file.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

namespace stereoball::simulator {
namespace {

const std::string kRandomizePath = std::string(SB_SOURCE_DIR) + "/config/randomize.yaml";

std::string shipped_text() {
  std::ifstream in(kRandomizePath);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The shipped text with the first occurrence of from replaced by to.
std::string edited(const std::string& from, const std::string& to) {
  std::string t = shipped_text();
  const auto at = t.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) t.replace(at, from.size(), to);
  return t;
}

TEST(RandomizeFile, ShippedRangesLoadAndMatchTheDefaults) {
  const auto r = load_randomize_ranges(kRandomizePath);
  ASSERT_TRUE(r.ok()) << r.error();
  const RandomizeRanges d;
  EXPECT_DOUBLE_EQ(r->ball_diameter_m.lo, 0.065);
  EXPECT_DOUBLE_EQ(r->ball_diameter_m.hi, 0.24);
  EXPECT_DOUBLE_EQ(r->ball_diameter_m.hi, d.ball_diameter_m.hi);
  EXPECT_EQ(r->floor_kind, d.floor_kind);
  EXPECT_EQ(r->leave_view, d.leave_view);
  EXPECT_DOUBLE_EQ(r->slow_turn_radps.hi, d.slow_turn_radps.hi);
  EXPECT_DOUBLE_EQ(r->sun_elevation_deg.lo, d.sun_elevation_deg.lo);
}

TEST(RandomizeFile, BadFilesAreRejectedWithFileAndKey) {
  struct Case {
    std::string from, to, key;
  };
  const Case cases[] = {
      {"diameter_m: [0.065, 0.24]", "diameter_m: [0.24, 0.065]", "ball.diameter_m"},
      {"diameter_m: [0.065, 0.24]", "diameter_m: [0.065]", "ball.diameter_m"},
      {"diameter_m: [0.065, 0.24]", "diameter_m: 0.1", "ball.diameter_m"},
      {"saturation: [0.55, 0.95]", "saturation: [0.55, 1.5]", "ball.saturation"},
      {"light_probability: 0.5", "light_probability: 2", "floor.light_probability"},
      {"{tiles: 1, planks: 1, carpet: 1, plain: 1}", "{tiles: 0, planks: 0, carpet: 0, plain: 0}",
       "floor.kind_weights"},
      {"{tiles: 1, planks: 1, carpet: 1, plain: 1}", "{tiles: 1, planks: 1, carpet: 1}",
       "floor.kind_weights.plain"},
      {"sun_elevation_deg: [25, 80]", "sun_elevation_deg: [25, 95]", "lighting.sun_elevation_deg"},
      {"kick_time_s: [2.0, 4.0]", "kick_time_s: [2.0, 40.0]", "leave_view.kick_time_s"},
      {"other_ball_min_size_ratio: 1.3", "other_ball_min_size_ratio: 0.5",
       "distractors.other_ball_min_size_ratio"},
      {"other_ball_min_size_ratio: 1.3", "other_ball_min_size_ratio: .nan",
       "distractors.other_ball_min_size_ratio"},
      {"walls:", "wals:", "walls.value"},
      {"duration_s: 10", "duration_s: 10\nextra_key: 1", "extra_key"},
  };
  for (const Case& c : cases) {
    const auto r = parse_randomize_ranges(edited(c.from, c.to), "bad.yaml");
    ASSERT_FALSE(r.ok()) << c.to;
    EXPECT_EQ(r.error().rfind("bad.yaml: ", 0), 0u) << r.error();
    EXPECT_NE(r.error().find(c.key), std::string::npos) << r.error();
  }
}

TEST(RandomizeFile, MissingFileIsNamed) {
  const auto r = load_randomize_ranges("/nonexistent/randomize.yaml");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("/nonexistent/randomize.yaml"), std::string::npos);
}

}  // namespace
}  // namespace stereoball::simulator
