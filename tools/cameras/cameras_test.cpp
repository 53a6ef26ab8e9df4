// Runs the real stereoball-cameras binary.

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <string>

namespace {

struct CamerasRun {
  int status = -1;
  std::string out;
};

CamerasRun run_cameras(const std::string& args) {
  CamerasRun r;
  const std::string cmd = std::string(SB_BIN_DIR) + "/stereoball-cameras " + args + " 2>&1";
  FILE* p = ::popen(cmd.c_str(), "r");
  if (p == nullptr) return r;
  std::array<char, 512> buf{};
  while (std::fgets(buf.data(), buf.size(), p) != nullptr) r.out += buf.data();
  r.status = ::pclose(p);
  return r;
}

TEST(StereoballCameras, GivenNoMatchingDevicesWhenListedThenClearMessageAndSuccess) {
  const CamerasRun r = run_cameras("--glob '/nonexistent/video*'");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("No video devices found"), std::string::npos) << r.out;
}

TEST(StereoballCameras, GivenNamedMissingDeviceWhenListedThenOneLineAndFailure) {
  const CamerasRun r = run_cameras("--device /dev/video_missing_42");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.out.find("/dev/video_missing_42: open failed: no such device"), std::string::npos)
      << r.out;
}

TEST(StereoballCameras, GivenNonV4l2DeviceWhenListedThenSaysSoAndFailure) {
  const CamerasRun r = run_cameras("--device /dev/null");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.out.find("not a V4L2 video device"), std::string::npos) << r.out;
}

TEST(StereoballCameras, GivenHelpWhenAskedThenDescribesTheTool) {
  const CamerasRun r = run_cameras("--help");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("--device"), std::string::npos);
  EXPECT_NE(r.out.find("frame rates"), std::string::npos);
}

}  // namespace
