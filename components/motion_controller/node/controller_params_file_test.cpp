#include "motion_controller/node/controller_params_file.hpp"

#include <gtest/gtest.h>

#include "common/params/field_table_testing.hpp"

#include <fstream>
#include <sstream>

namespace stereoball::motion_controller {
namespace {

std::string shipped_config() {
  std::ifstream in(std::string(SB_SOURCE_DIR) + "/config/motion_controller.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

Result<MotionControllerNodeParams> parse(const std::string& text) {
  auto file = params::ParamsFile::parse(text, "mc.yaml");
  if (!file) return Error{file.error()};
  return read_controller_params(*file);
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

TEST(ControllerParamsFile, GivenShippedConfig_ThenLoadsAndEqualsCoreDefaultsAt20Hz) {
  const auto p =
      load_controller_params(std::string(SB_SOURCE_DIR) + "/config/motion_controller.yaml");
  ASSERT_TRUE(p.ok()) << p.error();
  const MotionControllerParams d;
  EXPECT_EQ(p->rate_hz, 20.0);
  EXPECT_EQ(p->controller.target_distance_m, d.target_distance_m);
  EXPECT_EQ(p->controller.bearing_gain_per_s, d.bearing_gain_per_s);
  EXPECT_EQ(p->controller.max_angular_jerk_radps3, d.max_angular_jerk_radps3);
  EXPECT_EQ(p->controller.search_timeout_ns, d.search_timeout_ns);
  EXPECT_EQ(p->controller.stale_timeout_ns, 300'000'000);
  EXPECT_EQ(p->controller.search_left_when_unknown, d.search_left_when_unknown);
}

TEST(ControllerParamsFile, GivenChangedValues_ThenRead) {
  std::string text = replaced(shipped_config(), "target_distance_m: 1.0", "target_distance_m: 1.5");
  text = replaced(text, "search_left_when_unknown: true", "search_left_when_unknown: false");
  const auto p = parse(text);
  ASSERT_TRUE(p.ok()) << p.error();
  EXPECT_EQ(p->controller.target_distance_m, 1.5);
  EXPECT_FALSE(p->controller.search_left_when_unknown);
}

TEST(ControllerParamsFile, GivenSearchFasterThanMaxAngular_ThenValidateErrorNamesField) {
  const auto p =
      parse(replaced(shipped_config(), "search_angular_radps: 0.8", "search_angular_radps: 3.0"));
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.error().find("search_angular_radps"), std::string::npos) << p.error();
  EXPECT_NE(p.error().find("mc.yaml"), std::string::npos) << p.error();
}

TEST(ControllerParamsFile, GivenUnknownOrMissingKey_ThenErrorNamesKey) {
  const auto typo = parse(replaced(shipped_config(), "rate_hz:", "rate:"));
  ASSERT_FALSE(typo.ok());
  EXPECT_NE(typo.error().find("rate"), std::string::npos) << typo.error();
  const auto range = parse(replaced(shipped_config(), "rate_hz: 20.0", "rate_hz: 0"));
  ASSERT_FALSE(range.ok());
  EXPECT_NE(range.error().find("rate_hz"), std::string::npos) << range.error();
}

TEST(ControllerParamsFile, GivenFieldTableThenShippedFileDefaultsRoundTripAndRefusalsHold) {
  params::testing::expect_table_contract(
      node_params_fields(), std::string(SB_SOURCE_DIR) + "/config/motion_controller.yaml");
}

TEST(ControllerParamsFile, GivenReadmeThenItsParameterTableIsTheGeneratedOne) {
  params::testing::expect_readme_table(
      node_params_fields(), std::string(SB_SOURCE_DIR) + "/components/motion_controller/README.md");
}

}  // namespace
}  // namespace stereoball::motion_controller
