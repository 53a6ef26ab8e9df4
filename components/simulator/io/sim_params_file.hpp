#pragma once
// config/simulator.yaml -> SimParams, through the common params loader (every key required).

#include <string>

#include "common/params/params_file.hpp"
#include "common/util/result.hpp"
#include "simulator/core/sim_params.hpp"

namespace stereoball::simulator {

/// Reads every SimParams key from an already opened params file (keys as in simulator.yaml);
/// problems are recorded in file (see ParamsFile::finish()).
void read_sim_params(params::ParamsFile& file, SimParams& p);

/// Loads and validates a simulator params file.
Result<SimParams> load_sim_params(const std::string& path);

}  // namespace stereoball::simulator
