#include "common/node/common_flags.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "common/dds/participant.hpp"
#include "common/util/install_layout.hpp"

namespace stereoball::node {

std::string default_config_path(const std::string& file_name) {
  return paths::shipped_config_path(file_name);
}

void add_common_flags(CLI::App& app, CommonOptions& options, const std::string& config_name,
                      bool with_config) {
  options.domain_id = dds::domain_from_env(0);
  if (with_config) {
    app.add_option("-c,--config", options.config_path,
                   "parameters file (YAML); default: " + config_name +
                       " from $STEREOBALL_CONFIG_DIR, /etc/stereoball, the installed files or "
                       "the source tree, first found");
    // Resolved once the command line is parsed, so --help works without any file.
    app.parse_complete_callback([&app, &options, config_name] {
      // An absolute default (test programs) is used as given, like --config.
      if (options.config_path.empty() && std::filesystem::path(config_name).is_absolute()) {
        options.config_path = config_name;
      }
      auto found = options.config_path.empty()
                       ? paths::find_config(config_name, paths::default_roots())
                       : paths::check_explicit(options.config_path);
      if (!found) throw CLI::ValidationError("--config", found.error());
      options.config_path = found->path.string();
      options.config_origin = found->origin;
      std::fprintf(stderr, "%s: parameters from %s (%s)\n",
                   std::filesystem::path(app.get_name()).filename().c_str(),
                   options.config_path.c_str(), options.config_origin.c_str());
    });
  }
  app.add_option("--domain", options.domain_id, "DDS domain id (default: $STEREOBALL_DOMAIN or 0)")
      ->check(CLI::Range(0, 232))
      ->capture_default_str();
  app.add_option("--partition", options.partition, "DDS partition (default: none)");
  app.add_option("--log-level", options.log_level, "debug, info, warn or error")
      ->check(CLI::IsMember({"debug", "info", "warn", "error"}))
      ->capture_default_str();
}

}  // namespace stereoball::node
