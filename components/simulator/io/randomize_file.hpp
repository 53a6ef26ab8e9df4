#pragma once
// config/randomize.yaml -> RandomizeRanges, through the common params loader (every key
// required, unknown keys rejected, errors name the file and key).

#include <string>

#include "common/params/params_file.hpp"
#include "common/util/result.hpp"
#include "simulator/core/randomize.hpp"

namespace stereoball::simulator {

/// Reads every range from an opened params file; problems are recorded in file.
void read_randomize_ranges(params::ParamsFile& file, RandomizeRanges& r);

/// Loads and validates a range file.
Result<RandomizeRanges> load_randomize_ranges(const std::string& path);

/// Same from YAML text; name stands for the file in messages.
Result<RandomizeRanges> parse_randomize_ranges(const std::string& text, const std::string& name);

}  // namespace stereoball::simulator
