#include "camera_server/node/camera_server_params_file.hpp"

#include <gtest/gtest.h>

#include "common/params/field_table_testing.hpp"

namespace stereoball::camera_server {
namespace {

bool has(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

TEST(CameraServerParamsFile, GivenShippedConfigsWhenLoadedThenValid) {
  auto v4l2 = load_camera_server_params(SB_SOURCE_DIR "/config/camera_server.yaml");
  ASSERT_TRUE(v4l2.ok()) << v4l2.error();
  EXPECT_EQ(v4l2->source, "v4l2");
  EXPECT_EQ(v4l2->effective_skew_ns(), 16'666'666);
  auto files = load_camera_server_params(SB_SOURCE_DIR "/config/camera_server_files.yaml");
  ASSERT_TRUE(files.ok()) << files.error();
  EXPECT_EQ(files->source, "files");
}

TEST(CameraServerParamsFile, GivenControlsWhenParsedThenNestedKeysRead) {
  auto p = parse_camera_server_params(
      "source: v4l2\nwidth_px: 320\nheight_px: 240\nrate_hz: 15\n"
      "controls:\n  auto_exposure: false\n  exposure_us: 5000\n  gain: 3\n",
      "t.yaml");
  ASSERT_TRUE(p.ok()) << p.error();
  EXPECT_FALSE(p->controls.auto_exposure);
  EXPECT_EQ(p->controls.exposure_us, 5000);
  EXPECT_EQ(p->controls.gain, 3);
  EXPECT_EQ(p->width_px, 320u);
}

TEST(CameraServerParamsFile, GivenTypoInControlsWhenParsedThenUnknownKeyNamed) {
  auto p = parse_camera_server_params(
      "source: v4l2\nwidth_px: 640\nheight_px: 480\nrate_hz: 30\ncontrols:\n  gian: 3\n", "t.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_TRUE(has(p.error(), "controls.gian")) << p.error();
}

TEST(CameraServerParamsFile, GivenSameDeviceTwiceWhenParsedThenErrorNamesFileAndDevice) {
  auto p = parse_camera_server_params(
      "source: v4l2\nwidth_px: 640\nheight_px: 480\nrate_hz: 30\n"
      "left_device: /dev/video2\nright_device: /dev/video2\n",
      "cams.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_TRUE(has(p.error(), "cams.yaml")) << p.error();
  EXPECT_TRUE(has(p.error(), "same device")) << p.error();
}

TEST(CameraServerParamsFile, GivenMissingRequiredKeyOrBadChoiceWhenParsedThenNamed) {
  auto missing = parse_camera_server_params("source: v4l2\nwidth_px: 640\nrate_hz: 30\n", "t.yaml");
  ASSERT_FALSE(missing.ok());
  EXPECT_TRUE(has(missing.error(), "height_px")) << missing.error();
  auto bad = parse_camera_server_params("source: usb\nwidth_px: 640\nheight_px: 480\nrate_hz: 30\n",
                                        "t.yaml");
  ASSERT_FALSE(bad.ok());
  EXPECT_TRUE(has(bad.error(), "source")) << bad.error();
}

TEST(CameraServerParamsFile, GivenFrameEncodingKeysWhenParsedThenReadOrNamedWithTheFile) {
  const std::string base = "source: v4l2\nwidth_px: 640\nheight_px: 480\nrate_hz: 30\n";
  // Absent: raw (today's behaviour)
  auto absent = parse_camera_server_params(base, "c.yaml");
  ASSERT_TRUE(absent.ok()) << absent.error();
  EXPECT_EQ(absent->output.frame_encoding, "raw");
  EXPECT_EQ(absent->output.jpeg_quality, 90);
  EXPECT_EQ(absent->output.jpeg_chroma, "444");
  // Set: read (the chroma as a bare number too, as a user writes it)
  auto jpeg = parse_camera_server_params(
      base + "frame_encoding: jpeg\njpeg_quality: 75\njpeg_chroma: 420\n", "c.yaml");
  ASSERT_TRUE(jpeg.ok()) << jpeg.error();
  EXPECT_EQ(jpeg->output.frame_encoding, "jpeg");
  EXPECT_EQ(jpeg->output.jpeg_quality, 75);
  EXPECT_EQ(jpeg->output.jpeg_chroma, "420");
  // Bad values: one line naming the file and the key
  for (const std::string bad :
       {"frame_encoding: webp\n", "jpeg_quality: 0\n", "jpeg_quality: 101\n",
        "jpeg_quality: high\n", "jpeg_chroma: 411\n", "jpeg_chroma: \"4:2:0\"\n"}) {
    auto p = parse_camera_server_params(base + bad, "c.yaml");
    ASSERT_FALSE(p.ok()) << bad;
    EXPECT_TRUE(has(p.error(), "c.yaml")) << p.error();
    EXPECT_TRUE(has(p.error(), bad.substr(0, bad.find(':')))) << p.error();
    EXPECT_FALSE(has(p.error(), "\n")) << p.error();
  }
  // Compressing needs decoded images: native camera bytes cannot be re-encoded
  auto native = parse_camera_server_params(base + "frame_encoding: png\npublish_encoding: native\n",
                                           "c.yaml");
  ASSERT_FALSE(native.ok());
  EXPECT_TRUE(has(native.error(), "publish_encoding")) << native.error();
}

TEST(CameraServerParamsFile, GivenFieldTableThenShippedFileDefaultsRoundTripAndRefusalsHold) {
  params::testing::expect_table_contract(camera_server_fields(),
                                         SB_SOURCE_DIR "/config/camera_server.yaml");
}

TEST(CameraServerParamsFile, GivenReadmeThenItsParameterTableIsTheGeneratedOne) {
  params::testing::expect_readme_table(camera_server_fields(),
                                       SB_SOURCE_DIR "/components/camera_server/README.md");
}

}  // namespace
}  // namespace stereoball::camera_server
