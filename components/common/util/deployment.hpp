#pragma once
// Which deployment a process belongs to, and so which Cyclone DDS configuration it uses. Every
// node and tool resolves it the same way, so an operator's tool (estop, topic, record, view,
// doctor) reaches the nodes a profile or a systemd role started without naming a file:
//   1. $CYCLONEDDS_URI, when set, as given (the operator chose);
//   2. the profile's `cyclonedds:` file (deploy/<profile>.yaml, its `{config}/NAME` found by
//      the configuration search order of install_layout.hpp), the profile being
//      $STEREOBALL_PROFILE, else `robot` when $STEREOBALL_IFACE is set (every LAN profile uses
//      cyclonedds/lan.xml), else `all-in-one` (cyclonedds/loopback.xml).
// The variables are read after the roles' settings file (/etc/stereoball/stereoball.env, or
// $STEREOBALL_ENV_FILE; "" = none) has filled those the environment does not set, as systemd
// gives them to the units' nodes. Keyless processes ignore all this: the DDS layer confines
// them to loopback.

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "common/util/install_layout.hpp"
#include "common/util/result.hpp"

namespace stereoball::deployment {

/// The roles' settings file: $STEREOBALL_ENV_FILE if set (empty = none), else
/// /etc/stereoball/stereoball.env.
std::optional<std::filesystem::path> env_file_path();

/// The KEY=VALUE assignments of a systemd EnvironmentFile (blank lines, `#`/`;` comments,
/// values optionally in single or double quotes). Errors name file_name and the line.
Result<std::vector<std::pair<std::string, std::string>>> parse_env_file(std::string_view text,
                                                                        std::string_view file_name);

/// What import_env_file() did (for the log and `stereoball doctor`).
struct EnvFileImport {
  std::string file;              ///< the settings file read ("" = none exists)
  std::vector<std::string> set;  ///< variables taken from it (the environment lacked them)
  std::string error;             ///< why it could not be used ("" = fine)
};

/// Once per process: sets every variable of the settings file that the environment does not
/// set (the environment wins). A missing file sets nothing; an unreadable or malformed one
/// sets nothing and is reported in `error` (and logged once as a warning).
const EnvFileImport& import_env_file();

/// A profile's DDS configuration file, found as the launcher finds it.
struct ProfileDds {
  std::string profile;  ///< profile name
  std::string file;     ///< absolute path ("" = the profile sets none)
  std::string origin;   ///< which rule of the search order found it ("installed files", ...)
};

/// Reads `cyclonedds:` of deploy/<name_or_path>.yaml under the data root of roots.
Result<ProfileDds> profile_dds_file(const std::string& name_or_path,
                                    const paths::SearchRoots& roots);

/// The configuration chosen, and why.
struct DdsConfig {
  std::string uri;                ///< value for CYCLONEDDS_URI ("" = Cyclone's defaults)
  std::string origin;             ///< e.g. "profile all-in-one (default: ...)", "$CYCLONEDDS_URI"
  std::string profile;            ///< the profile it came from ("" when $CYCLONEDDS_URI chose)
  bool from_environment = false;  ///< $CYCLONEDDS_URI was set
};

/// What the resolution looks at (this process's environment, or fixed values in tests).
struct DdsConfigInputs {
  std::optional<std::string> cyclonedds_uri;  ///< $CYCLONEDDS_URI
  std::optional<std::string> profile;         ///< $STEREOBALL_PROFILE
  std::string profile_source;                 ///< where profile came from, for origin
  bool lan_interface = false;                 ///< $STEREOBALL_IFACE is set
  std::function<Result<ProfileDds>(const std::string& profile)> profile_dds;
};

/// The deployment's DDS configuration by the order at the top of this file. An error (an
/// unknown profile, a missing file) names what was looked for.
Result<DdsConfig> resolve_dds_config(const DdsConfigInputs& inputs);

/// This process's inputs (after import_env_file()) resolved; not cached, changes nothing.
/// `stereoball doctor` compares it with what the nodes report.
Result<DdsConfig> deployment_dds_config();

/// Once per process, before Cyclone reads its configuration (the DDS layer calls it before the
/// first keyed participant): imports the settings file, resolves, sets CYCLONEDDS_URI when it
/// was unset, and logs the choice (info). Returns the same answer on every call.
const Result<DdsConfig>& use_deployment_dds_config();

/// "file://" + an absolute path (the form CYCLONEDDS_URI takes).
std::string file_uri(const std::filesystem::path& path);

}  // namespace stereoball::deployment
