#include "simulator/io/sim_params_file.hpp"

#include "common/params/field_table_yaml.hpp"

namespace stereoball::simulator {
namespace {

params::FieldTable<SimulatorConfig> make_table() {
  auto table = params::section("", &SimulatorConfig::sim, sim_fields());
  const auto output = params::section("", &SimulatorConfig::output, stereo::frame_codec_fields());
  // After frame_rate_hz, where config/simulator.yaml has them.
  table.fields.insert(table.fields.begin() + 3, output.fields.begin(), output.fields.end());
  return table;
}

}  // namespace

const params::FieldTable<SimulatorConfig>& simulator_config_fields() {
  return params::table_of(make_table);
}

Result<SimulatorConfig> load_simulator_config(const std::string& path) {
  return params::load_fields(simulator_config_fields(), path);
}

Result<SimParams> load_sim_params(const std::string& path) {
  auto c = load_simulator_config(path);
  if (!c) return Error{c.error()};
  return c->sim;
}

}  // namespace stereoball::simulator
