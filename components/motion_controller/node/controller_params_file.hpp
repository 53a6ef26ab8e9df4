#pragma once
// The motion_controller process's parameters (core + node) and their file
// (config/motion_controller.yaml), read through one field table.

#include <string>

#include "common/params/field_table.hpp"
#include "common/params/params_file.hpp"
#include "common/util/result.hpp"
#include "motion_controller/core/controller_params.hpp"

namespace stereoball::motion_controller {

/// Everything the motion_controller process is configured with.
struct MotionControllerNodeParams {
  MotionControllerNodeParams();       ///< every field at its default from node_params_fields()
  MotionControllerParams controller;  ///< the core's parameters (keys = field names)
  double rate_hz;                     ///< minimum cmd/velocity rate

  /// Success, or the first field out of its range, naming key, range and unit.
  Status validate() const;
};

/// rate_hz plus every field of controller_fields().
const params::FieldTable<MotionControllerNodeParams>& node_params_fields();

/// Reads every field from file and checks them.
Result<MotionControllerNodeParams> read_controller_params(params::ParamsFile& file);
/// Loads and checks the parameters at path; errors name the file and key.
Result<MotionControllerNodeParams> load_controller_params(const std::string& path);

}  // namespace stereoball::motion_controller
