#pragma once
// Loads BallDetectorParams from config/ball_detector.yaml through detector_fields() (every key
// required, unknown keys are errors, messages name the file and key).

#include <string>

#include "ball_detector/pipeline/detector_params.hpp"
#include "common/params/params_file.hpp"
#include "common/util/result.hpp"

namespace stereoball::ball_detector {

/// Reads every ball detector key from an opened params file, then validates.
Result<BallDetectorParams> read_detector_params(params::ParamsFile& file);

/// Loads and validates the ball detector parameters from a YAML file.
Result<BallDetectorParams> load_detector_params(const std::string& path);

}  // namespace stereoball::ball_detector
