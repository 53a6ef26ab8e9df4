#include "common/util/deployment.hpp"

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <mutex>
#include <sstream>

#include "common/params/yaml_load.hpp"
#include "common/util/log.hpp"

namespace stereoball::deployment {
namespace fs = std::filesystem;

namespace {

constexpr const char* kDefaultEnvFile = "/etc/stereoball/stereoball.env";

std::optional<std::string> env(const char* name) {
  const char* value = std::getenv(name);
  if (!value) return std::nullopt;
  return std::string(value);
}

bool valid_name(std::string_view name) {
  if (name.empty() || std::isdigit(static_cast<unsigned char>(name[0]))) return false;
  for (char c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  }
  return true;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::string replace_all(std::string s, std::string_view what, std::string_view with) {
  std::string out;
  size_t from = 0;
  for (size_t pos; (pos = s.find(what, from)) != std::string::npos; from = pos + what.size()) {
    out.append(s, from, pos - from);
    out.append(with);
  }
  out.append(s, from, std::string::npos);
  return out;
}

}  // namespace

std::optional<fs::path> env_file_path() {
  if (const auto set = env("STEREOBALL_ENV_FILE")) {
    if (set->empty()) return std::nullopt;
    return fs::path(*set);
  }
  return fs::path(kDefaultEnvFile);
}

Result<std::vector<std::pair<std::string, std::string>>> parse_env_file(
    std::string_view text, std::string_view file_name) {
  std::vector<std::pair<std::string, std::string>> out;
  size_t line_no = 0;
  while (!text.empty()) {
    const size_t end = std::min(text.find('\n'), text.size());
    const std::string_view line = trim(text.substr(0, end));
    text.remove_prefix(std::min(end + 1, text.size()));
    ++line_no;
    if (line.empty() || line.front() == '#' || line.front() == ';') continue;
    const std::string where = std::string(file_name) + ": line " + std::to_string(line_no);
    const size_t eq = line.find('=');
    if (eq == std::string_view::npos) return Error{where + ": expected NAME=VALUE"};
    const std::string_view name = trim(line.substr(0, eq));
    if (!valid_name(name)) {
      return Error{where + ": '" + std::string(name) +
                   "' is not a variable name (letters, digits, _)"};
    }
    std::string_view value = trim(line.substr(eq + 1));
    if (value.size() >= 2 && (value.front() == '"' || value.front() == '\'') &&
        value.back() == value.front()) {
      value = value.substr(1, value.size() - 2);
    } else if (!value.empty() && (value.front() == '"' || value.front() == '\'')) {
      return Error{where + ": quote opened and not closed"};
    }
    out.emplace_back(std::string(name), std::string(value));
  }
  return out;
}

const EnvFileImport& import_env_file() {
  static EnvFileImport result;
  static std::once_flag once;
  std::call_once(once, [] {
    const auto path = env_file_path();
    if (!path) return;
    std::error_code ec;
    const bool named = env("STEREOBALL_ENV_FILE").has_value();
    if (!fs::exists(*path, ec)) {
      if (named) result.error = "$STEREOBALL_ENV_FILE names " + path->string() + ": no such file";
    } else {
      std::ifstream in(*path);
      if (!in) {
        result.error = "cannot read " + path->string() + " (" + std::strerror(errno) + ")";
      } else {
        std::stringstream text;
        text << in.rdbuf();
        auto parsed = parse_env_file(text.str(), path->string());
        if (!parsed) {
          result.error = parsed.error();
        } else {
          result.file = path->string();
          for (const auto& [name, value] : *parsed) {
            if (std::getenv(name.c_str())) continue;  // the environment wins
            ::setenv(name.c_str(), value.c_str(), 0);
            result.set.push_back(name);
          }
        }
      }
    }
    if (!result.error.empty()) {
      log::warn("deployment settings not applied: ", result.error,
                " (key file, profile, interface and peers must then come from the environment)");
    }
  });
  return result;
}

Result<ProfileDds> profile_dds_file(const std::string& name_or_path,
                                    const paths::SearchRoots& roots) {
  auto root = paths::data_root(roots);
  if (!root) return Error{root.error()};
  std::error_code ec;
  fs::path path = name_or_path;
  if (name_or_path.find('/') == std::string::npos || !fs::is_regular_file(path, ec)) {
    path = *root / "deploy" / (name_or_path + ".yaml");
  }
  if (!fs::is_regular_file(path, ec)) {
    return Error{"profile '" + name_or_path + "' not found (no " + path.string() + ")"};
  }
  auto parsed = params::load_yaml_file(path.string());
  if (!parsed) return Error{parsed.error()};
  ProfileDds out;
  out.profile = path.stem().string();
  const YAML::Node& doc = *parsed;
  if (!doc.IsMap()) return Error{path.string() + ": expected a mapping"};
  const YAML::Node value = doc["cyclonedds"];
  if (!value) return out;
  std::string file;
  try {
    file = value.as<std::string>();
  } catch (const YAML::Exception&) {
    return Error{path.string() + ": key 'cyclonedds': expected a file name"};
  }
  file = replace_all(file, "{root}", root->string());
  constexpr std::string_view kConfig = "{config}/";
  if (file.rfind(kConfig, 0) == 0) {
    auto found = paths::find_config(std::string_view(file).substr(kConfig.size()), roots);
    if (!found) return Error{path.string() + ": cyclonedds: " + found.error()};
    out.file = fs::absolute(found->path).lexically_normal().string();
    out.origin = found->origin;
  } else {
    out.file = fs::absolute(file).lexically_normal().string();
    out.origin = "named in " + path.string();
  }
  return out;
}

Result<DdsConfig> resolve_dds_config(const DdsConfigInputs& inputs) {
  if (inputs.cyclonedds_uri && !inputs.cyclonedds_uri->empty()) {
    DdsConfig config;
    config.uri = *inputs.cyclonedds_uri;
    config.origin = "$CYCLONEDDS_URI";
    config.from_environment = true;
    return config;
  }
  std::string profile, why;
  if (inputs.profile && !inputs.profile->empty()) {
    profile = *inputs.profile;
    why = inputs.profile_source.empty() ? "$STEREOBALL_PROFILE" : inputs.profile_source;
  } else if (inputs.lan_interface) {
    profile = "robot";
    why = "default of a LAN host: STEREOBALL_IFACE is set, STEREOBALL_PROFILE is not";
  } else {
    profile = "all-in-one";
    why = "default: neither STEREOBALL_PROFILE nor STEREOBALL_IFACE is set";
  }
  if (!inputs.profile_dds) return Error{"no way to read profile '" + profile + "'"};
  auto found = inputs.profile_dds(profile);
  if (!found) {
    return Error{"DDS configuration of profile '" + profile + "' (" + why + "): " + found.error()};
  }
  DdsConfig config;
  config.profile = found->profile;
  if (found->file.empty()) {
    config.origin =
        "profile " + found->profile + " (" + why + "), which names none: Cyclone's defaults";
    return config;
  }
  config.uri = file_uri(found->file);
  config.origin = "profile " + found->profile + " (" + why + "); file from " + found->origin;
  return config;
}

Result<DdsConfig> deployment_dds_config() {
  const EnvFileImport& imported = import_env_file();
  DdsConfigInputs inputs;
  inputs.cyclonedds_uri = env("CYCLONEDDS_URI");
  inputs.profile = env("STEREOBALL_PROFILE");
  for (const auto& name : imported.set) {
    if (name == "STEREOBALL_PROFILE")
      inputs.profile_source = "STEREOBALL_PROFILE in " + imported.file;
  }
  const auto iface = env("STEREOBALL_IFACE");
  inputs.lan_interface = iface && !iface->empty();
  inputs.profile_dds = [](const std::string& profile) {
    return profile_dds_file(profile, paths::default_roots());
  };
  return resolve_dds_config(inputs);
}

const Result<DdsConfig>& use_deployment_dds_config() {
  static std::optional<Result<DdsConfig>> result;
  static std::once_flag once;
  std::call_once(once, [] {
    result = deployment_dds_config();
    const EnvFileImport& imported = import_env_file();
    if (!imported.set.empty()) {
      std::string names;
      for (const auto& n : imported.set) names += (names.empty() ? "" : ", ") + n;
      log::info("deployment settings from ", imported.file, ": ", names);
    }
    if (!*result) return;
    const DdsConfig& config = **result;
    if (!config.from_environment && !config.uri.empty()) {
      ::setenv("CYCLONEDDS_URI", config.uri.c_str(), 1);
    }
    log::info("DDS configuration: ", config.uri.empty() ? "Cyclone's defaults" : config.uri, " (",
              config.origin, ")");
  });
  return *result;
}

std::string file_uri(const fs::path& path) {
  return "file://" + fs::absolute(path).lexically_normal().string();
}

}  // namespace stereoball::deployment
