// The production V4l2Device against the real kernel: error paths always, capture when a camera
// is attached (otherwise skipped with the reason).

#include "camera_server/io/v4l2_device.hpp"

#include <glob.h>
#include <gtest/gtest.h>

#include <cerrno>
#include <chrono>
#include <thread>

#include "camera_server/io/camera_opener.hpp"

namespace stereoball::camera_server {
namespace {

std::vector<std::string> video_nodes() {
  std::vector<std::string> out;
  glob_t g{};
  if (::glob("/dev/video*", 0, nullptr, &g) == 0) {
    for (size_t i = 0; i < g.gl_pathc; ++i) out.emplace_back(g.gl_pathv[i]);
  }
  ::globfree(&g);
  return out;
}

TEST(V4l2Device, GivenMissingNodeWhenOpenedThenNoSuchDevice) {
  V4l2Device dev;
  const DeviceStatus s = dev.open("/dev/video_does_not_exist");
  EXPECT_EQ(s.err, ENOENT);
  EXPECT_NE(s.message.find("no such device"), std::string::npos) << s.message;
}

TEST(V4l2Device, GivenRegularFileWhenOpenedThenNotADeviceNode) {
  V4l2Device dev;
  const DeviceStatus s = dev.open(SB_SOURCE_DIR "/CMakeLists.txt");
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message.find("not a device node"), std::string::npos) << s.message;
}

TEST(V4l2Device, GivenCharacterDeviceThatIsNotV4l2WhenQueriedThenNotAVideoDevice) {
  V4l2Device dev;
  ASSERT_TRUE(dev.open("/dev/null").ok());
  DeviceCaps caps;
  const DeviceStatus s = dev.query_caps(caps);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message.find("not a V4L2 video device"), std::string::npos) << s.message;
}

TEST(V4l2Device, GivenRealCameraWhenStreamingThenFramesHaveFormatSizeAndStamps) {
  const auto nodes = video_nodes();
  if (nodes.empty()) GTEST_SKIP() << "no /dev/video* on this machine: no camera to capture from";
  for (const auto& node : nodes) {
    V4l2Device dev;
    if (!dev.open(node).ok()) continue;
    DeviceCaps caps;
    std::vector<FormatOffer> offers;
    if (!dev.query_caps(caps).ok() || !caps.video_capture || !dev.enumerate_formats(offers).ok()) {
      continue;
    }
    // Take the first YUYV/MJPG size the camera offers.
    for (const auto& f : offers) {
      if ((f.fourcc != kFourccYuyv && f.fourcc != kFourccMjpeg) || f.sizes.empty()) continue;
      const SizeOffer& s = f.sizes.front();
      CameraConfig c;
      c.path = node;
      c.request = {f.fourcc == kFourccYuyv ? "yuyv" : "mjpeg", s.min_width_px, s.min_height_px,
                   s.rates_hz.empty() ? 30.0 : s.rates_hz.front()};
      OpenedCamera opened;
      const DeviceStatus st = open_camera(dev, c, opened);
      ASSERT_TRUE(st.ok()) << st.message;
      DequeuedFrame frame;
      DeviceStatus dq{EAGAIN, ""};
      for (int i = 0; i < 300 && dq.err == EAGAIN; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        dq = dev.dequeue(frame);
      }
      ASSERT_TRUE(dq.ok()) << dq.message;
      EXPECT_GT(frame.bytes, 0u);
      EXPECT_GT(frame.stamp_ns, 1'500'000'000'000'000'000);  // after 2017: an epoch stamp
      EXPECT_TRUE(dev.requeue(frame.index).ok());
      return;
    }
  }
  GTEST_SKIP() << "/dev/video* exists but no node offers YUYV or MJPEG capture";
}

}  // namespace
}  // namespace stereoball::camera_server
