#pragma once
// Loads the motion controller's parameters (core + node) from YAML
// (config/motion_controller.yaml).

#include <string>

#include "common/params/params_file.hpp"
#include "common/util/result.hpp"
#include "motion_controller/core/controller_params.hpp"

namespace stereoball::motion_controller {

/// Everything the motion_controller process is configured with.
struct MotionControllerNodeParams {
  MotionControllerParams controller;  ///< the core's parameters (keys = field names)
  double rate_hz = 20.0;              ///< cmd/velocity publishing rate, Hz
};

/// Reads every field from file (keys = field names, plus rate_hz) and validates them.
Result<MotionControllerNodeParams> read_controller_params(params::ParamsFile& file);
/// Loads and validates the parameters at path; errors name the file and key.
Result<MotionControllerNodeParams> load_controller_params(const std::string& path);

}  // namespace stereoball::motion_controller
