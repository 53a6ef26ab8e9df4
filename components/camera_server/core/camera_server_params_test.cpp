#include "camera_server/core/camera_server_params.hpp"

#include <gtest/gtest.h>

// GCC 12 reports a false -Wrestrict on std::string assignment from a literal (GCC PR 105651).
#pragma GCC diagnostic ignored "-Wrestrict"

namespace stereoball::camera_server {
namespace {

bool names(const Status& st, const char* field) {
  return !st && st.error().find(field) != std::string::npos;
}

TEST(CameraServerParams, GivenDefaultsWhenValidatedThenValidAndSkewIsHalfPeriod) {
  CameraServerParams p;
  EXPECT_TRUE(p.validate()) << p.validate().error();
  EXPECT_EQ(p.period_ns(), 33'333'333);
  EXPECT_EQ(p.effective_skew_ns(), 16'666'666);
  p.max_skew_ns = 5'000'000;
  EXPECT_EQ(p.effective_skew_ns(), 5'000'000);
}

TEST(CameraServerParams, GivenSameDeviceTwiceWhenValidatedThenErrorNamesDevice) {
  CameraServerParams p;
  p.right_device = p.left_device;
  EXPECT_TRUE(names(p.validate(), "same device"));
  EXPECT_TRUE(names(p.validate(), "/dev/video0"));
}

TEST(CameraServerParams, GivenBadFieldsWhenValidatedThenEachIsNamed) {
  auto error_after = [](auto mutate) {
    CameraServerParams p;
    mutate(p);
    return p.validate();
  };
  EXPECT_TRUE(names(error_after([](auto& p) { p.width_px = 641; }), "width_px"));
  EXPECT_TRUE(names(error_after([](auto& p) { p.rate_hz = 0; }), "rate_hz"));
  EXPECT_TRUE(names(error_after([](auto& p) { p.pixel_format.assign("h264"); }), "pixel_format"));
  EXPECT_TRUE(names(error_after([](auto& p) { p.rectify = true; }), "calibration_file"));
  EXPECT_TRUE(names(error_after([](auto& p) { p.controls.exposure_us = -3; }), "exposure_us"));
  EXPECT_TRUE(
      names(error_after([](auto& p) { p.output.frame_encoding.assign("gif"); }), "frame_encoding"));
  EXPECT_TRUE(names(error_after([](auto& p) { p.output.jpeg_quality = 0; }), "jpeg_quality"));
  EXPECT_TRUE(
      names(error_after([](auto& p) { p.output.jpeg_chroma.assign("411"); }), "jpeg_chroma"));
  EXPECT_TRUE(names(error_after([](auto& p) {
                      p.rectify = true;
                      p.calibration_file.assign("c.yaml");
                      p.publish_encoding.assign("native");
                    }),
                    "publish_encoding"));
}

TEST(CameraServerParams, GivenAPublishWidthThatCannotBeUsedWhenValidatedThenTheKeyIsNamed) {
  auto error_after = [](auto mutate) {
    CameraServerParams p;  // 640x480 cameras, bgr8
    mutate(p);
    return p.validate();
  };
  // Given widths that are odd, tiny, not smaller than the capture, or native passthrough
  EXPECT_TRUE(names(error_after([](auto& p) { p.publish_width_px = 321; }), "must be even"));
  EXPECT_TRUE(names(error_after([](auto& p) { p.publish_width_px = 8; }), "publish_width_px"));
  EXPECT_TRUE(names(error_after([](auto& p) { p.publish_width_px = 640; }), "smaller than"));
  EXPECT_TRUE(names(error_after([](auto& p) { p.publish_width_px = 1280; }), "publish_width_px"));
  EXPECT_TRUE(names(error_after([](auto& p) { p.publish_width_px = 9000; }), "publish_width_px"));
  EXPECT_TRUE(names(error_after([](auto& p) {
                      p.publish_width_px = 320;
                      p.publish_encoding.assign("native");
                    }),
                    "publish_width_px"));
  // Then a half width of decoded frames, or 0 (as captured), is accepted
  CameraServerParams p;
  p.publish_width_px = 320;
  EXPECT_TRUE(p.validate()) << p.validate().error();
  p.publish_width_px = 0;
  EXPECT_TRUE(p.validate()) << p.validate().error();
}

TEST(CameraServerParams, GivenFileSourceWhenInputsAmbiguousOrMissingThenError) {
  CameraServerParams p;
  p.source = "files";
  EXPECT_TRUE(names(p.validate(), "pairs_dir"));
  p.left_glob = "a/left*.jpg";
  EXPECT_TRUE(names(p.validate(), "right_glob"));
  p.right_glob = "a/right*.jpg";
  EXPECT_TRUE(p.validate());
  p.pairs_dir = "a";
  EXPECT_TRUE(names(p.validate(), "exactly one"));
}

}  // namespace
}  // namespace stereoball::camera_server
