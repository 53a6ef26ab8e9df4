#include "camera_server/core/device_errors.hpp"

#include <gtest/gtest.h>

#include <cerrno>

namespace stereoball::camera_server {
namespace {

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

TEST(ErrnoText, GivenCommonDeviceErrorsWhenMappedThenOneLineNamesDeviceOperationAndCause) {
  struct Case {
    int err;
    const char* cause;
  };
  for (const Case& c : {Case{ENOENT, "no such device"}, Case{EBUSY, "busy"},
                        Case{EACCES, "permission denied"}, Case{ENODEV, "disconnected"},
                        Case{ENOTTY, "not a V4L2 device"}, Case{ENOSPC, "bandwidth"}}) {
    const std::string t = errno_text(c.err, "/dev/video3", "open");
    EXPECT_TRUE(contains(t, "/dev/video3")) << t;
    EXPECT_TRUE(contains(t, "open failed")) << t;
    EXPECT_TRUE(contains(t, c.cause)) << t;
    EXPECT_FALSE(contains(t, "\n")) << t;
  }
}

TEST(ErrnoText, GivenUnusualErrnoWhenMappedThenFallsBackToSystemTextWithNumber) {
  const std::string t = errno_text(ELOOP, "/dev/video0", "VIDIOC_DQBUF");
  EXPECT_TRUE(contains(t, "VIDIOC_DQBUF"));
  EXPECT_TRUE(contains(t, "[errno " + std::to_string(ELOOP) + "]"));
}

TEST(ClassifyErrno, GivenErrnoValuesWhenClassifiedThenRecoveryMatchesCause) {
  EXPECT_EQ(classify_errno(EAGAIN), ErrorClass::kRetry);
  EXPECT_EQ(classify_errno(EINTR), ErrorClass::kRetry);
  EXPECT_EQ(classify_errno(ENODEV), ErrorClass::kDisconnected);
  EXPECT_EQ(classify_errno(EIO), ErrorClass::kDisconnected);
  EXPECT_EQ(classify_errno(EBUSY), ErrorClass::kFatal);
  EXPECT_EQ(classify_errno(ENOENT), ErrorClass::kFatal);
  EXPECT_EQ(classify_errno(EINVAL), ErrorClass::kFatal);
}

}  // namespace
}  // namespace stereoball::camera_server
