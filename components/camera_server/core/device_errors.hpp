#pragma once
// Turns errno values from device operations into one clear line and a recovery class.

#include <string>
#include <string_view>

namespace stereoball::camera_server {

/// What the capture loop should do about an error.
enum class ErrorClass {
  kRetry,         ///< transient (EINTR, EAGAIN): try the same call again
  kDisconnected,  ///< device vanished (unplugged, ENODEV): close, reopen with back-off
  kFatal,         ///< configuration problem (missing, busy, permissions, unsupported): report
};

/// Recovery class of an errno value.
ErrorClass classify_errno(int err);

/// One line naming the device, the operation and the likely cause, e.g.
/// "/dev/video0: open failed: device is busy (another program is using the camera)".
std::string errno_text(int err, std::string_view device, std::string_view operation);

}  // namespace stereoball::camera_server
