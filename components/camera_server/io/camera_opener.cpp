#include "camera_server/io/camera_opener.hpp"

#include <sys/stat.h>

#include <cerrno>

namespace stereoball::camera_server {

CameraConfig camera_config(const CameraServerParams& p, const std::string& path) {
  CameraConfig c;
  c.path = path;
  c.request = FormatRequest{p.pixel_format, p.width_px, p.height_px, p.rate_hz};
  c.controls = p.controls;
  c.buffer_count = p.buffer_count;
  return c;
}

namespace {

DeviceStatus configure(VideoDevice& device, const CameraConfig& config, OpenedCamera& opened) {
  if (auto s = device.open(config.path); !s.ok()) return s;
  if (auto s = device.query_caps(opened.caps); !s.ok()) return s;
  if (!opened.caps.video_capture) {
    return {ENOTTY, config.path + " (" + opened.caps.card +
                        ") is not a video capture device (UVC cameras also create metadata "
                        "nodes; try the neighbouring /dev/videoN, see `stereoball cameras`)"};
  }
  if (!opened.caps.streaming) {
    return {ENOTTY, config.path + " (" + opened.caps.card + ") does not support streaming I/O"};
  }
  std::vector<FormatOffer> offers;
  if (auto s = device.enumerate_formats(offers); !s.ok()) return s;
  auto choice = negotiate_format(offers, config.request, config.path);
  if (!choice) return {EINVAL, choice.error()};
  if (auto s = device.set_format(*choice, opened.format); !s.ok()) return s;
  for (const auto& control : map_controls(config.controls)) {
    if (auto s = device.set_control(control); !s.ok()) opened.warnings.push_back(s.message);
  }
  return device.start_streaming(config.buffer_count);
}

}  // namespace

DeviceStatus open_camera(VideoDevice& device, const CameraConfig& config, OpenedCamera& opened) {
  opened = OpenedCamera{};
  DeviceStatus s = configure(device, config, opened);
  if (!s.ok()) device.close();
  return s;
}

Status check_distinct_devices(const std::string& left, const std::string& right) {
  if (left == right) {
    return Error{"left and right camera are the same device (" + left +
                 "); give two different cameras"};
  }
  struct stat a {};
  struct stat b {};
  if (::stat(left.c_str(), &a) != 0 || ::stat(right.c_str(), &b) != 0) return {};
  if (S_ISCHR(a.st_mode) && S_ISCHR(b.st_mode) && a.st_rdev == b.st_rdev) {
    return Error{"left camera " + left + " and right camera " + right +
                 " are the same device; give two different cameras"};
  }
  return {};
}

}  // namespace stereoball::camera_server
