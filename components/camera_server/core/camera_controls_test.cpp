#include "camera_server/core/camera_controls.hpp"

#include <gtest/gtest.h>
#include <linux/videodev2.h>

namespace stereoball::camera_server {
namespace {

const ControlSetting* find(const std::vector<ControlSetting>& v, uint32_t id) {
  for (const auto& c : v) {
    if (c.id == id) return &c;
  }
  return nullptr;
}

size_t index_of(const std::vector<ControlSetting>& v, uint32_t id) {
  for (size_t i = 0; i < v.size(); ++i) {
    if (v[i].id == id) return i;
  }
  return v.size();
}

TEST(MapControls, GivenDefaultsWhenMappedThenAutoModesOnAndNothingManual) {
  const auto v = map_controls(CameraControls{});
  ASSERT_NE(find(v, V4L2_CID_EXPOSURE_AUTO), nullptr);
  EXPECT_EQ(find(v, V4L2_CID_EXPOSURE_AUTO)->value, V4L2_EXPOSURE_APERTURE_PRIORITY);
  ASSERT_NE(find(v, V4L2_CID_AUTO_WHITE_BALANCE), nullptr);
  EXPECT_EQ(find(v, V4L2_CID_AUTO_WHITE_BALANCE)->value, 1);
  EXPECT_EQ(find(v, V4L2_CID_EXPOSURE_ABSOLUTE), nullptr);
  EXPECT_EQ(find(v, V4L2_CID_GAIN), nullptr);
  EXPECT_EQ(find(v, V4L2_CID_WHITE_BALANCE_TEMPERATURE), nullptr);
}

TEST(MapControls, GivenManualExposureWhenMappedThenAutoOffFirstAndValueIn100usUnits) {
  CameraControls c;
  c.auto_exposure = false;
  c.exposure_us = 8'040;  // 80.4 units -> 80
  const auto v = map_controls(c);
  EXPECT_EQ(find(v, V4L2_CID_EXPOSURE_AUTO)->value, V4L2_EXPOSURE_MANUAL);
  ASSERT_NE(find(v, V4L2_CID_EXPOSURE_ABSOLUTE), nullptr);
  EXPECT_EQ(find(v, V4L2_CID_EXPOSURE_ABSOLUTE)->value, 80);
  EXPECT_LT(index_of(v, V4L2_CID_EXPOSURE_AUTO), index_of(v, V4L2_CID_EXPOSURE_ABSOLUTE));
}

TEST(MapControls, GivenTinyManualExposureWhenMappedThenAtLeastOneUnit) {
  CameraControls c;
  c.auto_exposure = false;
  c.exposure_us = 10;
  EXPECT_EQ(find(map_controls(c), V4L2_CID_EXPOSURE_ABSOLUTE)->value, 1);
}

TEST(MapControls, GivenExposureButAutoOnWhenMappedThenManualValueNotSent) {
  CameraControls c;
  c.exposure_us = 5000;
  EXPECT_EQ(find(map_controls(c), V4L2_CID_EXPOSURE_ABSOLUTE), nullptr);
}

TEST(MapControls, GivenGainAndManualWhiteBalanceWhenMappedThenBothSetAndAutoWbOffFirst) {
  CameraControls c;
  c.gain = 12;
  c.auto_white_balance = false;
  c.white_balance_temperature_k = 4500;
  const auto v = map_controls(c);
  EXPECT_EQ(find(v, V4L2_CID_GAIN)->value, 12);
  EXPECT_EQ(find(v, V4L2_CID_AUTO_WHITE_BALANCE)->value, 0);
  EXPECT_EQ(find(v, V4L2_CID_WHITE_BALANCE_TEMPERATURE)->value, 4500);
  EXPECT_LT(index_of(v, V4L2_CID_AUTO_WHITE_BALANCE),
            index_of(v, V4L2_CID_WHITE_BALANCE_TEMPERATURE));
}

TEST(CameraControls, GivenOutOfRangeValuesWhenValidatedThenFieldIsNamed) {
  CameraControls c;
  c.white_balance_temperature_k = 50;
  ASSERT_FALSE(c.validate());
  EXPECT_NE(c.validate().error().find("white_balance_temperature_k"), std::string::npos);
  c = CameraControls{};
  c.gain = -5;
  EXPECT_NE(c.validate().error().find("gain"), std::string::npos);
  EXPECT_TRUE(CameraControls{}.validate());
}

}  // namespace
}  // namespace stereoball::camera_server
