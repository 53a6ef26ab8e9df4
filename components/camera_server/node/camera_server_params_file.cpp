#include "camera_server/node/camera_server_params_file.hpp"

#include "common/params/field_table_yaml.hpp"

namespace stereoball::camera_server {

Result<CameraServerParams> load_camera_server_params(const std::string& path) {
  return params::load_fields(camera_server_fields(), path);
}

Result<CameraServerParams> parse_camera_server_params(const std::string& text,
                                                      const std::string& name) {
  return params::parse_fields(camera_server_fields(), text, name);
}

}  // namespace stereoball::camera_server
