#include "tracker/node/tracker_params_file.hpp"

#include <gtest/gtest.h>

#include "common/params/field_table_testing.hpp"

#include <fstream>
#include <sstream>

namespace stereoball::tracker {
namespace {

std::string shipped_config() {
  std::ifstream in(std::string(SB_SOURCE_DIR) + "/config/tracker.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(TrackerParamsFile, GivenShippedConfig_ThenLoadsAndEqualsCoreDefaults) {
  const auto p = load_tracker_params(std::string(SB_SOURCE_DIR) + "/config/tracker.yaml");
  ASSERT_TRUE(p.ok()) << p.error();
  const TrackerParams d;
  EXPECT_EQ(p->ssd_threshold, d.ssd_threshold);
  EXPECT_EQ(p->register_size, d.register_size);
  EXPECT_EQ(p->line_tolerance_m, d.line_tolerance_m);
  EXPECT_EQ(p->register_max_age_ns, d.register_max_age_ns);
  EXPECT_EQ(p->lost_after_ns, d.lost_after_ns);
  EXPECT_EQ(p->side_min_speed_mps, d.side_min_speed_mps);
}

TEST(TrackerParamsFile, GivenChangedThreshold_ThenValueIsRead) {
  std::string text = shipped_config();
  const auto at = text.find("ssd_threshold: 200000");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 21, "ssd_threshold: 150000");
  auto file = params::ParamsFile::parse(text, "t.yaml");
  ASSERT_TRUE(file.ok());
  const auto p = read_tracker_params(*file);
  ASSERT_TRUE(p.ok()) << p.error();
  EXPECT_EQ(p->ssd_threshold, 150000.0);
}

TEST(TrackerParamsFile, GivenMissingKey_ThenErrorNamesKey) {
  std::string text = shipped_config();
  const auto at = text.find("line_tolerance_m:");
  text.replace(at, 17, "line_tolerance:");  // a typo
  auto file = params::ParamsFile::parse(text, "t.yaml");
  ASSERT_TRUE(file.ok());
  const auto p = read_tracker_params(*file);
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.error().find("line_tolerance"), std::string::npos) << p.error();
  EXPECT_NE(p.error().find("t.yaml"), std::string::npos) << p.error();
}

TEST(TrackerParamsFile, GivenOutOfRangeValue_ThenErrorNamesKey) {
  std::string text = shipped_config();
  const auto at = text.find("register_size: 5");
  text.replace(at, 16, "register_size: 1");
  auto file = params::ParamsFile::parse(text, "t.yaml");
  ASSERT_TRUE(file.ok());
  const auto p = read_tracker_params(*file);
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.error().find("register_size"), std::string::npos) << p.error();
}

TEST(TrackerParamsFile, GivenMissingFile_ThenErrorNamesPath) {
  const auto p = load_tracker_params("/nonexistent/tracker.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.error().find("/nonexistent/tracker.yaml"), std::string::npos) << p.error();
}

TEST(TrackerParamsFile, GivenFieldTableThenShippedFileDefaultsRoundTripAndRefusalsHold) {
  params::testing::expect_table_contract(tracker_fields(),
                                         std::string(SB_SOURCE_DIR) + "/config/tracker.yaml");
}

TEST(TrackerParamsFile, GivenReadmeThenItsParameterTableIsTheGeneratedOne) {
  params::testing::expect_readme_table(
      tracker_fields(), std::string(SB_SOURCE_DIR) + "/components/tracker/README.md");
}

}  // namespace
}  // namespace stereoball::tracker
