#include "tracker/node/tracker_params_file.hpp"

#include "common/params/field_table_yaml.hpp"

namespace stereoball::tracker {

Result<TrackerParams> read_tracker_params(params::ParamsFile& file) {
  return params::read_fields(tracker_fields(), file);
}

Result<TrackerParams> load_tracker_params(const std::string& path) {
  return params::load_fields(tracker_fields(), path);
}

}  // namespace stereoball::tracker
