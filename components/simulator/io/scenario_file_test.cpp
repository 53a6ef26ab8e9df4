#include "simulator/io/scenario_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>

namespace stereoball::simulator {
namespace {

const std::string kDir = std::string(SB_SOURCE_DIR) + "/config/scenarios";

TEST(ScenarioFile, EveryShippedScenarioLoadsAndValidates) {
  // Given the scenario folder with at least the eight required scenarios
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kDir)) {
    if (entry.path().extension() != ".yaml") continue;
    // When each is loaded
    const auto s = load_scenario(entry.path().string());
    // Then it is valid and its name matches the file name
    ASSERT_TRUE(s.ok()) << s.error();
    EXPECT_EQ(s->name, entry.path().stem().string());
    ++count;
  }
  EXPECT_GE(count, 8);
  for (const char* name :
       {"ball_still", "ball_rolling_across", "ball_rolling_away", "ball_leaves_left",
        "ball_leaves_right", "no_ball", "lighting_change", "two_round_objects"}) {
    EXPECT_TRUE(load_scenario_by_name(name, kDir).ok()) << name;
  }
}

TEST(ScenarioFile, ValuesAndDefaultsAreRead) {
  // Given a small scenario
  const auto s = parse_scenario(
      "name: t\nseed: 9\nball: {x_m: 2.0, vy_mps: -0.5, color_a: [10, 20, 30]}\n"
      "boxes:\n  - {x_m: 1.0, y_m: 2.0, size_z_m: 0.7}\n"
      "door_frames:\n  - {x_m: 6.0, y_m: 0.0, along: y}\n"
      "kicks:\n  - {t_s: 1.5, vx_mps: 0.3}\n",
      "inline");
  // Then given keys are taken and the rest keeps its defaults
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_EQ(s->seed, 9u);
  ASSERT_TRUE(s->ball.has_value());
  EXPECT_DOUBLE_EQ(s->ball->x_m, 2.0);
  EXPECT_DOUBLE_EQ(s->ball->vy_mps, -0.5);
  EXPECT_DOUBLE_EQ(s->ball->color_a.g, 20.0);
  EXPECT_DOUBLE_EQ(s->ball->radius_m, BallSpec{}.radius_m);
  ASSERT_EQ(s->boxes.size(), 1u);
  EXPECT_DOUBLE_EQ(s->boxes[0].size_z_m, 0.7);
  EXPECT_FALSE(s->door_frames[0].along_x);
  EXPECT_DOUBLE_EQ(s->kicks[0].t_s, 1.5);
}

struct BadCase {
  const char* text;
  const char* must_mention;
};

class BadScenario : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadScenario, ErrorNamesTheKey) {
  // Given an invalid scenario text
  const auto s = parse_scenario(GetParam().text, "bad.yaml");
  // Then loading fails with a message naming the file and the offending key
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().find("bad.yaml"), std::string::npos) << s.error();
  EXPECT_NE(s.error().find(GetParam().must_mention), std::string::npos) << s.error();
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadScenario,
    ::testing::Values(
        BadCase{"name: t\nbal: {x_m: 1}\n", "'bal': unknown key"},
        BadCase{"name: t\nball: {x_m: 1, radius: 0.1}\n", "ball.radius"},
        BadCase{"name: t\nball: {x_m: one}\n", "ball.x_m': expected a number"},
        BadCase{"name: t\nball: {x_m: 1, radius_m: -0.1}\n", "ball.radius_m"},
        BadCase{"name: t\nboxes:\n  - {x_m: 1}\n  - {x_m: 1, size_x_m: 0}\n", "boxes[1].size_x_m"},
        BadCase{"name: t\nboxes: {x_m: 1}\n", "'boxes': expected a list"},
        BadCase{"name: t\nplates:\n  - {center_m: [1, 2]}\n", "plates[0].center_m"},
        BadCase{"name: t\ndoor_frames:\n  - {along: z}\n", "door_frames[0].along"},
        BadCase{"name: t\nlighting:\n  - {t_s: 2}\n  - {t_s: 1}\n", "lighting[1].t_s"},
        BadCase{"name: t\nkicks:\n  - {t_s: 1}\n", "kicks"},
        BadCase{"name: t\nball: {pattern: dots}\n", "ball.pattern"},
        BadCase{"name: t\nroom: {floor_pattern: marble}\n", "room.floor_pattern"},
        BadCase{"name: t\nrobot: {max_angular_radps: 0}\n", "robot.max_angular_radps"},
        BadCase{"name: t\nspheres:\n  - {center_m: [2, 0, 0.01], radius_m: 0.1}\n",
                "spheres[0].center_m.z"},
        BadCase{"name: t\nseed: -3\n", "'seed'"}, BadCase{"name: [t\n", "not valid YAML"},
        BadCase{"- 1\n- 2\n", "expected a mapping"},
        BadCase{"name: t\nball:\n  x_m: 1\n  x_m: 2\n",
                "key 'ball.x_m' appears twice (lines 3 and 4)"}));

TEST(ScenarioFile, RandomisedWorldKeysAreRead) {
  const auto s = parse_scenario(
      "name: t\nroom: {floor_pattern: planks}\nrobot: {max_angular_radps: 0.4}\n"
      "ball: {pattern: stripes}\nspheres:\n  - {center_m: [2, 1, 0.1], radius_m: 0.1, color: [1, "
      "2, 3]}\n",
      "ok.yaml");
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_EQ(s->room.floor_pattern, FloorPattern::kPlanks);
  EXPECT_EQ(s->ball->pattern, BallPattern::kStripes);
  ASSERT_TRUE(s->robot_max_angular_radps.has_value());
  EXPECT_DOUBLE_EQ(*s->robot_max_angular_radps, 0.4);
  ASSERT_EQ(s->spheres.size(), 1u);
  EXPECT_DOUBLE_EQ(s->spheres[0].color.b, 3.0);
}

TEST(ScenarioFile, CalibrationSceneIsRead) {
  // Given a calibration scene with two poses and free-running eyes
  const auto s = parse_scenario(
      "name: c\ncalibration:\n  board: {inner_corners: [7, 5], square_m: 0.04}\n"
      "  eye_skew_ms: 15\n  poses:\n    - {z_m: 0.7, tilt_y_deg: 30, hold_s: 2, move_s: 0.5}\n"
      "    - {x_m: 0.1, z_m: 0.9, roll_deg: -10, hold_s: 1}\n",
      "calib.yaml");
  // Then the board, the skew (seconds), the poses (radians) and the duration (the poses') are read
  ASSERT_TRUE(s.ok()) << s.error();
  ASSERT_TRUE(s->calibration.has_value());
  const CalibrationScene& c = *s->calibration;
  EXPECT_EQ(c.board.cols, 7);
  EXPECT_EQ(c.board.rows, 5);
  EXPECT_DOUBLE_EQ(c.board.square_m, 0.04);
  EXPECT_DOUBLE_EQ(c.eye_skew_s, 0.015);
  ASSERT_EQ(c.holds.size(), 2u);
  EXPECT_NEAR(c.holds[0].pose.tilt_y_rad, 30 * M_PI / 180, 1e-12);
  EXPECT_NEAR(c.holds[1].pose.roll_rad, -10 * M_PI / 180, 1e-12);
  EXPECT_DOUBLE_EQ(s->duration_s, 3.5);
}

TEST(ScenarioFile, BadCalibrationSceneNamesTheKey) {
  const std::pair<const char*, const char*> cases[] = {
      {"name: c\ncalibration: {board: {inner_corners: [9]}, random_poses: {count: 3}}\n",
       "calibration.board.inner_corners"},
      {"name: c\ncalibration: {poses: [{z_m: 0.6, tilt_deg: 3}]}\n",
       "calibration.poses[0].tilt_deg': unknown key"},
      {"name: c\ncalibration: {poses: [{z_m: 0.05}]}\n", "calibration.poses[0].z_m"},
      {"name: c\ncalibration: {random_poses: {count: 2.5}}\n", "calibration.random_poses.count"},
      {"name: c\ncalibration: {eye_skew_ms: 5000, random_poses: {count: 3}}\n",
       "calibration.eye_skew_ms"},
      {"name: c\ncalibration: {}\n", "calibration.poses"}};
  for (const auto& [text, expected] : cases) {
    const auto s = parse_scenario(text, "bad.yaml");
    ASSERT_FALSE(s.ok()) << text;
    EXPECT_NE(s.error().find("bad.yaml"), std::string::npos) << s.error();
    EXPECT_NE(s.error().find(expected), std::string::npos) << s.error();
  }
}

TEST(ScenarioFile, MissingFileIsAClearError) {
  // Given a name with no file
  const auto s = load_scenario_by_name("no_such_scenario", kDir);
  // Then the error names the scenario and the path looked at
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().find("no_such_scenario"), std::string::npos);
}

}  // namespace
}  // namespace stereoball::simulator
