#include "camera_server/core/device_errors.hpp"

#include <cerrno>
#include <cstring>

namespace stereoball::camera_server {

ErrorClass classify_errno(int err) {
  switch (err) {
    case EINTR:
    case EAGAIN:
      return ErrorClass::kRetry;
    case ENODEV:
    case ENXIO:
    case EIO:
    case EPIPE:
    case ESHUTDOWN:
      return ErrorClass::kDisconnected;
    default:
      return ErrorClass::kFatal;
  }
}

namespace {

std::string cause(int err) {
  switch (err) {
    case ENOENT:
      return "no such device (camera not plugged in? run `stereoball cameras` to list devices)";
    case EBUSY:
      return "device is busy (another program is using the camera; check with `fuser -v <device>`)";
    case EACCES:
    case EPERM:
      return "permission denied (add the user to the 'video' group)";
    case ENODEV:
    case ENXIO:
      return "device disconnected (camera unplugged?)";
    case EIO:
      return "I/O error (USB cable, hub power or bandwidth?)";
    case ENOTTY:
      return "not a V4L2 device (the ioctl is not supported by this file)";
    case EINVAL:
      return "invalid argument (the driver rejected the request)";
    case ENOMEM:
      return "out of memory for capture buffers (fewer buffers or a smaller size may help)";
    case ENOSPC:
      return "not enough USB bandwidth (use MJPEG, a lower size/rate, or separate USB ports)";
    case EAGAIN:
      return "no frame ready yet";
    case EINTR:
      return "interrupted by a signal";
    default:
      return std::strerror(err);
  }
}

}  // namespace

std::string errno_text(int err, std::string_view device, std::string_view operation) {
  std::string line(device);
  line += ": ";
  line += operation;
  line += " failed: ";
  line += cause(err);
  line += " [errno " + std::to_string(err) + "]";
  return line;
}

}  // namespace stereoball::camera_server
