#include "common/node/common_flags.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include "common/util/cli11.hpp"

#include "common/dds/participant.hpp"
#include "common/util/deployment.hpp"
#include "common/util/install_layout.hpp"

namespace stereoball::node {

std::string default_config_path(const std::string& file_name) {
  return paths::shipped_config_path(file_name);
}

void add_common_flags(CLI::App& app, CommonOptions& options, const std::string& config_name,
                      bool with_config) {
  // The roles' settings file fills what the environment lacks before the defaults below read
  // it (a tool run by hand on a robot gets the role's domain, partition and key file).
  deployment::import_env_file();
  options.domain_id = dds::domain_from_env(0);
  if (with_config) {
    app.add_option("-c,--config", options.config_path,
                   "parameters file (YAML); default: " + config_name +
                       " from $STEREOBALL_CONFIG_DIR, /etc/stereoball, the installed files or "
                       "the source tree, first found");
    // Resolved once the command line is parsed, so --help works without any file.
    app.parse_complete_callback([&options, config_name] {
      // A path given with --config (or an absolute default, for test programs) is used as
      // given: the params loader names it if it cannot be read.
      if (!options.config_path.empty() || std::filesystem::path(config_name).is_absolute()) {
        if (options.config_path.empty()) options.config_path = config_name;
        options.config_origin = "--config";
        return;
      }
      auto found = paths::find_config(config_name, paths::default_roots());
      // Exit status 2, as for every other configuration error of a node.
      if (!found) throw CLI::Error("ConfigError", "--config: " + found.error(), 2);
      options.config_path = found->path.string();
      options.config_origin = found->origin;
    });
  }
  app.add_option("--domain", options.domain_id, "DDS domain id (default: $STEREOBALL_DOMAIN or 0)")
      ->check(CLI::Range(0, 232))
      ->capture_default_str();
  if (const char* partition = std::getenv("STEREOBALL_PARTITION")) options.partition = partition;
  app.add_option("--partition", options.partition,
                 "DDS partition (default: $STEREOBALL_PARTITION or none)");
  options.key_file = dds::resolve_key_file(std::nullopt);
  app.add_option("--key-file", options.key_file,
                 "deployment key file (default: $STEREOBALL_KEY_FILE; none = unauthenticated, "
                 "loopback only)");
  app.add_option("--log-level", options.log_level, "debug, info, warn or error")
      ->check(CLI::IsMember({"debug", "info", "warn", "error"}))
      ->capture_default_str();
}

void add_help_params(CLI::App& app, const std::vector<params::FieldSpec>& specs) {
  // Option callbacks run before the parse-complete callback that searches for --config.
  app.add_flag_callback(
      "--help-params",
      [table = params::markdown_table(specs)] {
        std::cout << table;
        throw CLI::Success();
      },
      "print every parameter of the config file (key, default, allowed, unit, description) "
      "and exit");
}

}  // namespace stereoball::node
