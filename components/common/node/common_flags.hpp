#pragma once
// Flags every node and tool shares: --config, --domain, --partition, --log-level, --key-file.

#include <string>
#include <vector>

#include "common/params/field_table.hpp"

// Declared only: CLI/CLI.hpp costs seconds of compile time in every file that includes it, and
// this header reaches every node's files through node_runner.hpp.
namespace CLI {
class App;
}  // namespace CLI

namespace stereoball::node {

struct CommonOptions {
  std::string config_path;    ///< the component's YAML parameters (after the search)
  std::string config_origin;  ///< which rule of the search order found it (install_layout.hpp)
  int domain_id = 0;          ///< DDS domain (default: $STEREOBALL_DOMAIN or 0)
  std::string partition;      ///< DDS partition ("" = default)
  std::string log_level = "info";
  std::string key_file;  ///< deployment keys ("" = keyless, loopback only)
};

/// Adds the shared flags to app; with_config=false for tools that have no params file.
/// config_name ("tracker.yaml") is searched (common/util/install_layout.hpp) unless --config
/// names a file; after parsing, config_path holds the file and config_origin the rule that
/// found it (node::Runner logs both); a missing or unreadable file is a parse error that lists
/// what was tried.
void add_common_flags(CLI::App& app, CommonOptions& options, const std::string& config_name,
                      bool with_config = true);

/// Adds --help-params: prints the node's parameter table (key, default, allowed values, unit,
/// description; the markdown of the component README) and exits 0, without reading any file.
void add_help_params(CLI::App& app, const std::vector<params::FieldSpec>& specs);

/// Path of a shipped config file or folder by the search order of install_layout.hpp; if
/// nothing is found, the path the source tree would have (so the caller's open fails with it).
std::string default_config_path(const std::string& file_name);

}  // namespace stereoball::node
