#pragma once
// Loads TrackerParams from the tracker's YAML file (config/tracker.yaml).

#include <string>

#include "common/params/params_file.hpp"
#include "common/util/result.hpp"
#include "tracker/core/tracker_params.hpp"

namespace stereoball::tracker {

/// Reads every TrackerParams field (keys = field names) from file and validates them.
Result<TrackerParams> read_tracker_params(params::ParamsFile& file);
/// Loads and validates the tracker parameters at path; errors name the file and key.
Result<TrackerParams> load_tracker_params(const std::string& path);

}  // namespace stereoball::tracker
