#pragma once
// Maps the camera controls of the configuration to V4L2 control ids and values.

#include <cstdint>
#include <string>
#include <vector>

#include "camera_server/core/camera_server_params.hpp"

namespace stereoball::camera_server {

/// One VIDIOC_S_CTRL to issue: control id, value in driver units, readable name.
struct ControlSetting {
  uint32_t id = 0;
  int32_t value = 0;
  std::string name;
};

/// The controls to set, in the order they must be applied (auto modes off before manual values).
std::vector<ControlSetting> map_controls(const CameraControls& controls);

}  // namespace stereoball::camera_server
