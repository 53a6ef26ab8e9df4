#include "common/node/common_flags.hpp"

#include <cstdlib>
#include <filesystem>

#include "common/dds/participant.hpp"

#ifndef SB_DEFAULT_CONFIG_DIR
#define SB_DEFAULT_CONFIG_DIR "config"
#endif

namespace stereoball::node {

std::string default_config_path(const std::string& file_name) {
  if (const char* dir = std::getenv("STEREOBALL_CONFIG_DIR"); dir && *dir) {
    return (std::filesystem::path(dir) / file_name).string();
  }
  return (std::filesystem::path(SB_DEFAULT_CONFIG_DIR) / file_name).string();
}

void add_common_flags(CLI::App& app, CommonOptions& options, const std::string& default_config,
                      bool with_config) {
  options.domain_id = dds::domain_from_env(0);
  if (with_config) {
    options.config_path = default_config;
    app.add_option("-c,--config", options.config_path, "parameters file (YAML)")
        ->capture_default_str();
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

}  // namespace stereoball::node
