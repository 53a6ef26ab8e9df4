#include "motion_controller/node/controller_params_file.hpp"

#include "common/params/field_table_yaml.hpp"

namespace stereoball::motion_controller {
namespace {

using N = MotionControllerNodeParams;

params::FieldTable<N> make_table() {
  params::FieldTable<N> table = params::section("", &N::controller, controller_fields());
  table.fields.insert(table.fields.begin(),
                      params::number("rate_hz", params::at(&N::rate_hz), 20.0, {1.0, 1000.0}, "Hz",
                                     "minimum cmd/velocity rate without new tracks (each new "
                                     "track is answered at once)"));
  return table;
}

}  // namespace

SB_PARAMS_TABLE(MotionControllerNodeParams, node_params_fields, make_table)

Result<MotionControllerNodeParams> read_controller_params(params::ParamsFile& file) {
  return params::read_fields(node_params_fields(), file);
}

Result<MotionControllerNodeParams> load_controller_params(const std::string& path) {
  return params::load_fields(node_params_fields(), path);
}

}  // namespace stereoball::motion_controller
