#pragma once
// Where an installed or freshly built program finds its data (parameter files, scenarios,
// calibration, Cyclone DDS configurations, deploy profiles). The search order, first match wins:
//   1. an explicit path (--config FILE): used as given, never searched;
//   2. $STEREOBALL_CONFIG_DIR/<name>;
//   3. /etc/stereoball/<name>            (the administrator's overrides of single files);
//   4. <prefix>/share/stereoball/config/<name>  (what the package installed; <prefix> is found
//      from the program's own location, so an unpacked package works anywhere);
//   5. <source tree>/config/<name>       (only for a program run from the build tree it was
//      built in, so a moved or installed copy never reads a source checkout by accident).
// The first candidate that exists is used; if it cannot be read, that is an error (an
// override that is silently skipped would be worse than no override).

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/util/result.hpp"

namespace stereoball::paths {

/// The folders searched, in order; each may be absent.
struct SearchRoots {
  std::optional<std::filesystem::path> env_config_dir;  ///< $STEREOBALL_CONFIG_DIR
  std::optional<std::filesystem::path> etc_dir;         ///< /etc/stereoball
  std::optional<std::filesystem::path> share_dir;       ///< <prefix>/share/stereoball
  std::optional<std::filesystem::path> source_dir;      ///< the source tree (build-tree runs)
};

/// A file found by the search, and which rule found it (for the "using ..." log line).
struct Found {
  std::filesystem::path path;
  std::string origin;  ///< e.g. "/etc/stereoball", "$STEREOBALL_CONFIG_DIR"
};

/// The roots of this process: the environment, /etc/stereoball, and the folders derived from
/// the location of the running executable.
SearchRoots default_roots();

/// Roots for an executable at exe_path (pure apart from the existence checks it makes):
/// share_dir is <exe>/../share/stereoball or <exe>/../../share/stereoball (bin/ and
/// libexec/stereoball/), source_dir is set only when exe_path lies in build_bin_dirs.
SearchRoots roots_for_executable(const std::filesystem::path& exe_path,
                                 const std::vector<std::filesystem::path>& build_bin_dirs,
                                 const std::optional<std::filesystem::path>& source_dir);

/// Finds a configuration file or folder (e.g. "tracker.yaml", "scenarios",
/// "cyclonedds/lan.xml"). The error lists every place tried.
Result<Found> find_config(std::string_view name, const SearchRoots& roots);

/// find_config with this process's roots; if nothing is found, "config/<name>" (so the
/// caller's open fails naming a path). For defaults of tools that take a --config flag.
std::string shipped_config_path(std::string_view name);

/// The shipped config/ folder as a whole (data_root()/config), for benchmarks that read every
/// file of one consistent set; "config" if there is none.
std::string shipped_config_dir();

/// Checks a path given explicitly (--config): exists, is readable. Errors name the path.
Result<Found> check_explicit(const std::filesystem::path& path);

/// The folder that holds deploy/ profiles and the shipped config/: share_dir when installed,
/// else the source tree.
Result<std::filesystem::path> data_root(const SearchRoots& roots);

/// The folder of the running executable ("." if it cannot be read from /proc).
std::filesystem::path executable_dir();

}  // namespace stereoball::paths
