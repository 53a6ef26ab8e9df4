#include "camera_server/io/camera_opener.hpp"

#include <gtest/gtest.h>
#include <linux/videodev2.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>

#include "camera_server/io/fake_rig.hpp"

namespace stereoball::camera_server {
namespace {

using namespace testing;

CameraConfig config() {
  return camera_config(rig_params(), "/fake/left");
}

TEST(OpenCamera, GivenSupportedFormatWhenOpenedThenFormatSetControlsAppliedAndStreaming) {
  auto cam = make_camera();
  FakeVideoDevice dev(cam);
  CameraConfig c = config();
  c.controls.auto_exposure = false;
  c.controls.exposure_us = 10'000;
  OpenedCamera opened;
  const DeviceStatus s = open_camera(dev, c, opened);
  ASSERT_TRUE(s.ok()) << s.message;
  ASSERT_EQ(cam->formats_set.size(), 1u);
  EXPECT_EQ(cam->formats_set[0].fourcc, kFourccYuyv);
  EXPECT_EQ(opened.format.step_bytes, 2 * kW);
  EXPECT_EQ(cam->streams_started, 1);
  ASSERT_GE(cam->controls_set.size(), 2u);
  EXPECT_EQ(cam->controls_set[0].id, static_cast<uint32_t>(V4L2_CID_EXPOSURE_AUTO));
  EXPECT_EQ(cam->controls_set[1].id, static_cast<uint32_t>(V4L2_CID_EXPOSURE_ABSOLUTE));
  EXPECT_EQ(cam->controls_set[1].value, 100);
}

TEST(OpenCamera, GivenUnsupportedSizeWhenOpenedThenErrorListsOffersAndDeviceClosed) {
  auto cam = make_camera();
  FakeVideoDevice dev(cam);
  CameraConfig c = config();
  c.request.width_px = 1920;
  c.request.height_px = 1080;
  OpenedCamera opened;
  const DeviceStatus s = open_camera(dev, c, opened);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message.find("1920x1080"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("YUYV 64x48@30"), std::string::npos) << s.message;
  EXPECT_EQ(dev.poll_fd(), -1);
  EXPECT_EQ(cam->streams_started, 0);
}

TEST(OpenCamera, GivenMetadataNodeWhenOpenedThenNotACaptureDevice) {
  auto cam = make_camera();
  cam->caps.video_capture = false;
  FakeVideoDevice dev(cam);
  OpenedCamera opened;
  const DeviceStatus s = open_camera(dev, config(), opened);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message.find("not a video capture device"), std::string::npos) << s.message;
}

TEST(OpenCamera, GivenBusyOrMissingDeviceWhenOpenedThenCauseIsNamed) {
  for (auto [err, cause] : {std::pair{EBUSY, "busy"}, std::pair{ENOENT, "no such device"}}) {
    auto cam = make_camera();
    cam->open_errno = err;
    FakeVideoDevice dev(cam);
    OpenedCamera opened;
    const DeviceStatus s = open_camera(dev, config(), opened);
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.err, err);
    EXPECT_NE(s.message.find(cause), std::string::npos) << s.message;
    EXPECT_NE(s.message.find("/fake/left"), std::string::npos) << s.message;
  }
}

TEST(CheckDistinctDevices, GivenSamePathOrSymlinkToSameNodeThenErrorElseNone) {
  EXPECT_FALSE(check_distinct_devices("/dev/video0", "/dev/video0").ok());
  const auto dir =
      std::filesystem::temp_directory_path() / ("sb_cam_link_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto link = dir / "by-id-null";
  std::filesystem::remove(link);
  std::filesystem::create_symlink("/dev/null", link);
  const auto e = check_distinct_devices("/dev/null", link.string());
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.error().find("same device"), std::string::npos);
  EXPECT_TRUE(check_distinct_devices("/dev/null", "/dev/zero").ok());
  EXPECT_TRUE(check_distinct_devices("/dev/null", "/does/not/exist").ok());
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace stereoball::camera_server
