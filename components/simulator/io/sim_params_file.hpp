#pragma once
// config/simulator.yaml -> SimParams, through the common params loader (every key required).

#include <string>

#include "camera_server/core/frame_codec.hpp"
#include "common/params/params_file.hpp"
#include "common/util/result.hpp"
#include "simulator/core/sim_params.hpp"

namespace stereoball::simulator {

/// Reads every SimParams key from an already opened params file (keys as in simulator.yaml);
/// problems are recorded in file (see ParamsFile::finish()).
void read_sim_params(params::ParamsFile& file, SimParams& p);

/// Everything in config/simulator.yaml: the simulated hardware and how its frames are published.
struct SimulatorConfig {
  SimParams sim;                           ///< cameras, rig, base, ball, sensor
  camera_server::FrameCodecParams output;  ///< frame_encoding (raw|jpeg|png), jpeg_quality
};

/// Loads and validates a simulator params file (every key required).
Result<SimulatorConfig> load_simulator_config(const std::string& path);

/// Same, the simulated hardware only (the publishing keys are still checked).
Result<SimParams> load_sim_params(const std::string& path);

}  // namespace stereoball::simulator
