#pragma once
// config/simulator.yaml -> SimParams + how frames are published, through one field table
// (every key required).

#include <string>

#include "common/params/field_table.hpp"
#include "common/util/result.hpp"
#include "simulator/core/sim_params.hpp"
#include "stereo/frame/frame_codec.hpp"

namespace stereoball::simulator {

/// Everything in config/simulator.yaml: the simulated hardware and how its frames are published.
struct SimulatorConfig {
  SimParams sim;                    ///< cameras, rig, base, ball, sensor
  stereo::FrameCodecParams output;  ///< frame_encoding (raw|jpeg|png), jpeg_quality
};

/// Every key of config/simulator.yaml: sim_fields() plus frame_encoding and jpeg_quality.
const params::FieldTable<SimulatorConfig>& simulator_config_fields();

/// Loads and checks a simulator params file (every key required).
Result<SimulatorConfig> load_simulator_config(const std::string& path);

/// Same, the simulated hardware only (the publishing keys are still checked).
Result<SimParams> load_sim_params(const std::string& path);

}  // namespace stereoball::simulator
