#pragma once
// Opens and configures one camera (caps check, format negotiation, controls, streaming).

#include <optional>
#include <string>
#include <vector>

#include "camera_server/core/camera_server_params.hpp"
#include "camera_server/io/video_device.hpp"
#include "common/util/result.hpp"

namespace stereoball::camera_server {

/// How to set up one camera.
struct CameraConfig {
  std::string path;
  FormatRequest request;
  CameraControls controls;
  uint32_t buffer_count = 4;
};

/// What open_camera configured; warnings are controls the camera does not support.
struct OpenedCamera {
  DeviceCaps caps;
  ActiveFormat format;
  std::vector<std::string> warnings;
};

/// The camera config of one eye from the server params.
CameraConfig camera_config(const CameraServerParams& params, const std::string& path);

/// Opens `config.path` on `device` and starts streaming; on failure the device is closed and
/// the status holds one line naming the device and the problem.
DeviceStatus open_camera(VideoDevice& device, const CameraConfig& config, OpenedCamera& opened);

/// Error when both paths name the same camera (same path, or same device number through
/// symlinks such as /dev/v4l/by-id/...); success when they differ or cannot be compared.
Status check_distinct_devices(const std::string& left, const std::string& right);

}  // namespace stereoball::camera_server
