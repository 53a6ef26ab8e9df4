#include "ball_detector/pipeline/detector_params_file.hpp"

#include "common/params/field_table_yaml.hpp"

namespace stereoball::ball_detector {

Result<BallDetectorParams> read_detector_params(params::ParamsFile& file) {
  return params::read_fields(detector_fields(), file);
}

Result<BallDetectorParams> load_detector_params(const std::string& path) {
  return params::load_fields(detector_fields(), path);
}

}  // namespace stereoball::ball_detector
