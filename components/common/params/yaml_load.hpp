#pragma once
// Parses YAML text strictly: yaml-cpp keeps the first of two equal keys in a mapping and
// silently ignores the second, so a duplicated key is an error here, naming file, key and lines.

#include <yaml-cpp/yaml.h>

#include <optional>
#include <string>

#include "common/util/result.hpp"

namespace stereoball::params {

/// Success when every key is unique in its mapping anywhere under root; else an error naming the
/// first key that appears twice, as "key 'a.b' appears twice (lines 3 and 7)".
Status check_unique_keys(const YAML::Node& root);

/// Parses text (name is the file in error messages): "NAME: not valid YAML: ..." or
/// "NAME: key 'a.b' appears twice (lines 3 and 7)".
Result<YAML::Node> parse_yaml(const std::string& text, const std::string& name);

/// Reads and parses the file at path like parse_yaml.
Result<YAML::Node> load_yaml_file(const std::string& path);

}  // namespace stereoball::params
