// Loading config/ball_detector.yaml and rejecting bad files with clear messages.

#include "ball_detector/pipeline/detector_params_file.hpp"

#include <gtest/gtest.h>

#include "common/params/field_table_testing.hpp"

#include <fstream>
#include <sstream>

namespace sb = stereoball;

namespace {

std::string shipped_config() {
  std::ifstream in(std::string(SB_SOURCE_DIR) + "/config/ball_detector.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

sb::Result<sb::ball_detector::BallDetectorParams> parse(const std::string& text) {
  auto file = sb::params::ParamsFile::parse(text, "test.yaml");
  if (!file) return sb::Error{file.error()};
  return sb::ball_detector::read_detector_params(*file);
}

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

}  // namespace

TEST(DetectorParamsFile, GivenShippedConfig_ThenLoadsWithTheSimulatorBall) {
  const auto p = sb::ball_detector::load_detector_params(std::string(SB_SOURCE_DIR) +
                                                         "/config/ball_detector.yaml");
  ASSERT_TRUE(p.ok()) << p.error();
  EXPECT_DOUBLE_EQ(p->ball_diameter_m, 0.22);  // the simulator's ball: radius 0.11 m
  EXPECT_DOUBLE_EQ(p->epipolar_tolerance_px, 2.0);
  EXPECT_EQ(p->input, sb::ball_detector::DetectorInput::kColour);
  EXPECT_DOUBLE_EQ(p->p2p.edge.min_high_threshold, 24.0);
  EXPECT_EQ(p->p2p.max_peaks_examined, 16);
  EXPECT_DOUBLE_EQ(p->track_prior_gate_m, 0.3);
  EXPECT_EQ(p->track_prior_max_age_ns, 500'000'000);
  EXPECT_EQ(p->p2p.k_values, (std::vector<int>{3, 5}));
  EXPECT_TRUE(p->right_eye_partner_boxes);
  EXPECT_TRUE(p->predicted_partner);
  EXPECT_DOUBLE_EQ(p->predicted_partner_min_inside_fraction, 0.2);
  EXPECT_EQ(p->detector_params().max_circles, p->max_candidates_per_eye);
}

TEST(DetectorParamsFile, GivenChangedValues_ThenTheyAreUsed) {
  std::string text = replace(shipped_config(), "tolerance_px: 2.0", "tolerance_px: 1.5");
  text = replace(text, "k_values: [3, 5]", "k_values: [3, 8]");
  text = replace(text, "input: colour", "input: grey");
  text = replace(text, "max_peaks_examined: 16", "max_peaks_examined: 7");
  text = replace(text, "edge_min_threshold: 24", "edge_min_threshold: 40");
  text = replace(text, "right_eye_partner_boxes: true", "right_eye_partner_boxes: false");
  text = replace(text, "enabled: true", "enabled: false");
  text = replace(text, "min_inside_fraction: 0.2 ", "min_inside_fraction: 0.25 ");
  const auto p = parse(text);
  ASSERT_TRUE(p.ok()) << p.error();
  EXPECT_DOUBLE_EQ(p->epipolar_tolerance_px, 1.5);
  EXPECT_EQ(p->p2p.k_values, (std::vector<int>{3, 8}));
  EXPECT_EQ(p->input, sb::ball_detector::DetectorInput::kGrey);
  EXPECT_FALSE(p->right_eye_partner_boxes);
  EXPECT_FALSE(p->predicted_partner);
  EXPECT_DOUBLE_EQ(p->predicted_partner_min_inside_fraction, 0.25);
  EXPECT_EQ(p->p2p.max_peaks_examined, 7);
  EXPECT_DOUBLE_EQ(p->p2p.edge.min_high_threshold, 40.0);
}

TEST(DetectorParamsFile, GivenBadValues_ThenErrorNamesFileAndKey) {
  const std::string base = shipped_config();
  struct Case {
    std::string from, to, key;
  } cases[] = {
      {"diameter_m: 0.22", "diameter_m: -1", "ball.diameter_m"},
      {"enabled: true", "enabled: maybe", "predicted_partner.enabled"},
      {"min_inside_fraction: 0.2 ", "min_inside_fraction: 1.5 ",
       "predicted_partner.min_inside_fraction"},
      {"k_values: [3, 5]", "k_values: [2.5]", "p2p.k_values"},
      {"input: colour", "input: purple", "input"},
      {"max_peaks_examined: 16", "max_peaks_examined: 0", "p2p.max_peaks_examined"},
      {"gate_m: 0.3", "gate_m: -1", "track_prior.gate_m"},
      {"edge_min_threshold: 24", "edge_min_threshold: -3", "p2p.edge_min_threshold"},
      {"max_candidates_per_eye: 5", "max_candidates_per_eye: 0", "max_candidates_per_eye"},
      {"min_score: 0.55", "min_score: 1.5", "p2p.min_score"},
      {"rescue_weak_from: 0.4", "rescue_weak_from: nan", "p2p.rescue_weak_from"},
      {"max_candidates_per_eye: 5", "max_candidates_per_eye: 5\nunknown_key: 1", "unknown_key"},
  };
  for (const auto& c : cases) {
    const auto p = parse(replace(base, c.from, c.to));
    ASSERT_FALSE(p.ok()) << c.to;
    EXPECT_NE(p.error().find("test.yaml"), std::string::npos) << p.error();
    EXPECT_NE(p.error().find(c.key), std::string::npos) << p.error();
  }
}

TEST(DetectorParams, GivenDefaults_ThenValid) {
  EXPECT_TRUE(sb::ball_detector::BallDetectorParams{}.validate());
  sb::ball_detector::BallDetectorParams p;
  p.p2p.k_values = {};
  ASSERT_FALSE(p.validate());
  EXPECT_NE(p.validate().error().find("p2p.k_values"), std::string::npos);
}

TEST(DetectorInput, GivenEveryName_ThenRoundTrips) {
  for (const char* name : {"grey", "saturation", "value", "red", "green", "blue", "colour"}) {
    const auto input = sb::ball_detector::parse_detector_input(name);
    ASSERT_TRUE(input.has_value()) << name;
    EXPECT_STREQ(to_string(*input), name);
  }
  EXPECT_FALSE(sb::ball_detector::parse_detector_input("gray").has_value());
}

TEST(DetectorParamsFile, GivenFieldTableThenShippedFileDefaultsRoundTripAndRefusalsHold) {
  sb::params::testing::expect_table_contract(
      sb::ball_detector::detector_fields(),
      std::string(SB_SOURCE_DIR) + "/config/ball_detector.yaml");
}

TEST(DetectorParamsFile, GivenReadmeThenItsParameterTableIsTheGeneratedOne) {
  sb::params::testing::expect_readme_table(
      sb::ball_detector::detector_fields(),
      std::string(SB_SOURCE_DIR) + "/components/ball_detector/node/README.md");
}
