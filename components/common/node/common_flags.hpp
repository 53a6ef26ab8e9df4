#pragma once
// Flags every node and tool shares: --config, --domain, --partition, --log-level.

#include <CLI/CLI.hpp>

#include <string>

namespace stereoball::node {

struct CommonOptions {
  std::string config_path;    ///< the component's YAML parameters (after the search)
  std::string config_origin;  ///< which rule of the search order found it (install_layout.hpp)
  int domain_id = 0;          ///< DDS domain (default: $STEREOBALL_DOMAIN or 0)
  std::string partition;      ///< DDS partition ("" = default)
  std::string log_level = "info";
};

/// Adds the shared flags to app; with_config=false for tools that have no params file.
/// config_name ("tracker.yaml") is searched (common/util/install_layout.hpp) unless --config
/// names a file; after parsing, config_path holds the file and a line on stderr says which
/// file was used; a missing or unreadable file is a parse error that lists what was tried.
void add_common_flags(CLI::App& app, CommonOptions& options, const std::string& config_name,
                      bool with_config = true);

/// Path of a shipped config file or folder by the search order of install_layout.hpp; if
/// nothing is found, the path the source tree would have (so the caller's open fails with it).
std::string default_config_path(const std::string& file_name);

}  // namespace stereoball::node
