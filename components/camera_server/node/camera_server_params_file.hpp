#pragma once
// Loads CameraServerParams from the component's YAML file (config/camera_server.yaml).

#include <string>

#include "camera_server/core/camera_server_params.hpp"
#include "common/util/result.hpp"

namespace stereoball::camera_server {

/// Reads and validates the parameters; the error names the file and the key.
Result<CameraServerParams> load_camera_server_params(const std::string& path);

/// Same from YAML text; name stands in for the path in messages.
Result<CameraServerParams> parse_camera_server_params(const std::string& text,
                                                      const std::string& name);

}  // namespace stereoball::camera_server
