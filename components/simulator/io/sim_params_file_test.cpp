#include "simulator/io/sim_params_file.hpp"

#include <gtest/gtest.h>

#include "common/params/field_table_testing.hpp"

#include <fstream>
#include <sstream>
#include <tuple>
#include <vector>

namespace stereoball::simulator {
namespace {

const std::string kPath = std::string(SB_SOURCE_DIR) + "/config/simulator.yaml";

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(SimParamsFile, ShippedConfigLoadsAndMatchesTheDefaults) {
  // Given config/simulator.yaml
  const auto p = load_sim_params(kPath);
  // Then it is valid and documents the built-in defaults
  ASSERT_TRUE(p.ok()) << p.error();
  const SimParams d;
  EXPECT_EQ(p->width_px, d.width_px);
  EXPECT_DOUBLE_EQ(p->rig.baseline_m, d.rig.baseline_m);
  EXPECT_DOUBLE_EQ(p->left.distortion[0], d.left.distortion[0]);
  EXPECT_DOUBLE_EQ(p->rig.right_rotation_error_rad.y, d.rig.right_rotation_error_rad.y);
  EXPECT_EQ(p->robot.command_timeout_ns, d.robot.command_timeout_ns);
  EXPECT_DOUBLE_EQ(p->robot.max_linear_brake_mps2, d.robot.max_linear_brake_mps2);
  EXPECT_DOUBLE_EQ(p->robot.max_angular_brake_radps2, d.robot.max_angular_brake_radps2);
  // And publishes raw frames by default, quality 90 when switched to jpeg
  const auto c = load_simulator_config(kPath);
  ASSERT_TRUE(c.ok()) << c.error();
  EXPECT_EQ(c->output.frame_encoding, "raw");
  EXPECT_EQ(c->output.jpeg_quality, 90);
  EXPECT_EQ(c->output.jpeg_chroma, "444");
}

// The shipped config with one "key: value" line replaced, written to a temp file.
std::string config_with(const std::string& line, const std::string& replacement) {
  std::string text = read_text(kPath);
  const auto pos = text.find(line);
  EXPECT_NE(pos, std::string::npos) << line;
  if (pos != std::string::npos) text.replace(pos, line.size(), replacement);
  const std::string tmp = ::testing::TempDir() + "/sim_edited.yaml";
  std::ofstream(tmp) << text;
  return tmp;
}

TEST(SimParamsFile, FrameEncodingIsReadAndBadValuesAreNamedWithTheFile) {
  // Given frame_encoding jpeg
  const auto jpeg =
      load_simulator_config(config_with("frame_encoding: raw", "frame_encoding: jpeg"));
  ASSERT_TRUE(jpeg.ok()) << jpeg.error();
  EXPECT_EQ(jpeg->output.frame_encoding, "jpeg");
  // Then bad values are one line naming the file and the key, for every loader of the file
  for (const auto& [line, bad, key] :
       std::vector<std::tuple<std::string, std::string, std::string>>{
           {"frame_encoding: raw", "frame_encoding: webp", "frame_encoding"},
           {"jpeg_quality: 90", "jpeg_quality: 0", "jpeg_quality"},
           {"jpeg_quality: 90", "jpeg_quality: 101", "jpeg_quality"},
           {"jpeg_chroma: \"444\"", "jpeg_chroma: 411", "jpeg_chroma"}}) {
    const std::string path = config_with(line, bad);
    const auto c = load_simulator_config(path);
    ASSERT_FALSE(c.ok()) << bad;
    EXPECT_NE(c.error().find(path), std::string::npos) << c.error();
    EXPECT_NE(c.error().find(key), std::string::npos) << c.error();
    EXPECT_EQ(c.error().find('\n'), std::string::npos) << c.error();
    const auto p = load_sim_params(path);
    ASSERT_FALSE(p.ok()) << bad;
    EXPECT_NE(p.error().find(key), std::string::npos) << p.error();
  }
}

TEST(SimParamsFile, BrakeLimitsAreReadAndRangeChecked) {
  const auto p =
      load_sim_params(config_with("max_linear_brake_mps2: 4.0", "max_linear_brake_mps2: 6.5"));
  ASSERT_TRUE(p.ok()) << p.error();
  EXPECT_DOUBLE_EQ(p->robot.max_linear_brake_mps2, 6.5);
  const auto bad =
      load_sim_params(config_with("max_angular_brake_radps2: 16.0", "max_angular_brake_radps2: 0"));
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("robot.max_angular_brake_radps2"), std::string::npos) << bad.error();
}

TEST(SimParamsFile, BadValueIsNamed) {
  // Given the shipped config with a negative baseline written to a temp file
  std::string text = read_text(kPath);
  const auto pos = text.find("baseline_m: 0.12");
  ASSERT_NE(pos, std::string::npos);
  text.replace(pos, 16, "baseline_m: -0.5");
  const std::string tmp = ::testing::TempDir() + "/sim_bad.yaml";
  std::ofstream(tmp) << text;
  // When loaded
  const auto p = load_sim_params(tmp);
  // Then the error names the key
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.error().find("rig.baseline_m"), std::string::npos) << p.error();
}

TEST(SimParamsFile, UnknownKeyIsNamed) {
  // Given the shipped config with a misspelt extra key
  const std::string tmp = ::testing::TempDir() + "/sim_unknown.yaml";
  std::ofstream(tmp) << read_text(kPath) << "noise_sigma: 3\n";
  // Then loading reports it
  const auto p = load_sim_params(tmp);
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.error().find("noise_sigma"), std::string::npos) << p.error();
}

TEST(SimParamsFile, GivenFieldTableThenShippedFileDefaultsRoundTripAndRefusalsHold) {
  params::testing::expect_table_contract(simulator_config_fields(), kPath);
}

TEST(SimParamsFile, GivenReadmeThenItsParameterTableIsTheGeneratedOne) {
  params::testing::expect_readme_table(
      simulator_config_fields(), std::string(SB_SOURCE_DIR) + "/components/simulator/README.md");
}

}  // namespace
}  // namespace stereoball::simulator
