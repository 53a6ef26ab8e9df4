#pragma once
// Flags every node and tool shares: --config, --domain, --partition, --log-level, --key-file.

#include <CLI/CLI.hpp>

#include <string>

namespace stereoball::node {

struct CommonOptions {
  std::string config_path;  ///< the component's YAML parameters
  int domain_id = 0;        ///< DDS domain (default: $STEREOBALL_DOMAIN or 0)
  std::string partition;    ///< DDS partition ("" = default)
  std::string log_level = "info";
  std::string key_file;  ///< deployment keys ("" = keyless, loopback only)
};

/// Adds the shared flags to app; with_config=false for tools that have no params file.
void add_common_flags(CLI::App& app, CommonOptions& options, const std::string& default_config,
                      bool with_config = true);

/// Default path of a config file: $STEREOBALL_CONFIG_DIR/<file> or <source>/config/<file>.
std::string default_config_path(const std::string& file_name);

}  // namespace stereoball::node
