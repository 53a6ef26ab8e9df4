#pragma once
// Scenario files (config/scenarios/*.yaml): strict YAML with defaults; errors name file and key.

#include <string>

#include "common/util/result.hpp"
#include "simulator/core/scenario.hpp"

namespace stereoball::simulator {

/// Parses scenario YAML text and validates it; source names the text in error messages.
Result<Scenario> parse_scenario(const std::string& text, const std::string& source);

/// Reads and validates a scenario file.
Result<Scenario> load_scenario(const std::string& path);

/// A scenario given by name ("ball_still", looked up as <dir>/<name>.yaml) or by path
/// (anything containing '/' or ending in .yaml).
Result<Scenario> load_scenario_by_name(const std::string& name_or_path, const std::string& dir);

}  // namespace stereoball::simulator
