#pragma once
// Launch profiles (deploy/*.yaml): which nodes run on a host, with which arguments, config
// and Cyclone DDS configuration. Profiles are data; the supervisor runs them.

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "common/util/result.hpp"

namespace stereoball::launch {

/// One node of a profile.
struct NodeSpec {
  std::string name;               ///< unique within the profile, e.g. "tracker"
  std::string program;            ///< program in build/bin, e.g. "tracker"
  std::vector<std::string> args;  ///< arguments (paths relative to the project root)
  bool restart = true;            ///< restart when it exits with an error or crashes
  bool optional = false;          ///< skip (with a note) if the program is not built
};

struct Profile {
  std::string name;
  std::string description;
  std::string cyclonedds_config;  ///< file for CYCLONEDDS_URI ("" = leave the environment alone)
  std::vector<NodeSpec> nodes;
};

/// Finds a shipped configuration file by name ("tracker.yaml", "cyclonedds/lan.xml").
using ConfigLookup = std::function<Result<std::string>(std::string_view name)>;

/// Loads a profile by path or by name (deploy/<name>.yaml under root_dir). Errors name the key.
/// "{root}" in arguments becomes root_dir; "{config}/NAME" becomes the file that lookup finds
/// (so /etc/stereoball overrides single files; without lookup, root_dir/config/NAME).
Result<Profile> load_profile(const std::string& name_or_path, const std::string& root_dir,
                             const ConfigLookup& lookup = {});

/// Replaces "{root}" in every argument with root_dir (profiles stay relocatable).
void expand_root(Profile& profile, const std::string& root_dir);

/// Replaces every "{config}/NAME" argument (and the cyclonedds file) by lookup(NAME).
Result<Profile> expand_config(Profile profile, const ConfigLookup& lookup);

}  // namespace stereoball::launch
