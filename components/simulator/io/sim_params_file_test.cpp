#include "simulator/io/sim_params_file.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

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

}  // namespace
}  // namespace stereoball::simulator
