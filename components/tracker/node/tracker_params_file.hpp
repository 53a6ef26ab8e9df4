#pragma once
// Loads TrackerParams from the tracker's YAML file (config/tracker.yaml) through its field table.

#include <string>

#include "common/params/params_file.hpp"
#include "common/util/result.hpp"
#include "tracker/core/tracker_params.hpp"

namespace stereoball::tracker {

/// Reads every field of tracker_fields() from file and checks them.
Result<TrackerParams> read_tracker_params(params::ParamsFile& file);
/// Loads and checks the tracker parameters at path; errors name the file and key.
Result<TrackerParams> load_tracker_params(const std::string& path);

}  // namespace stereoball::tracker
