#include "profile.hpp"

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <optional>
#include <set>

#include "common/params/yaml_load.hpp"

namespace stereoball::launch {
namespace fs = std::filesystem;

namespace {
Result<NodeSpec> parse_node(const YAML::Node& node, const std::string& where) {
  if (!node.IsMap()) return Error{where + ": expected a mapping with name, program, args"};
  NodeSpec spec;
  for (const auto& item : node) {
    const std::string key = item.first.as<std::string>();
    try {
      if (key == "name")
        spec.name = item.second.as<std::string>();
      else if (key == "program")
        spec.program = item.second.as<std::string>();
      else if (key == "args")
        spec.args = item.second.as<std::vector<std::string>>();
      else if (key == "restart")
        spec.restart = item.second.as<bool>();
      else if (key == "optional")
        spec.optional = item.second.as<bool>();
      else
        return Error{where + ": key '" + key +
                     "': unknown (allowed: name, program, args, restart, optional)"};
    } catch (const YAML::Exception&) {
      return Error{where + ": key '" + key + "': wrong type"};
    }
  }
  if (spec.name.empty()) return Error{where + ": key 'name': missing"};
  if (spec.program.empty()) return Error{where + ": key 'program': missing"};
  if (spec.program.find('/') != std::string::npos) {
    return Error{where + ": key 'program': give a program name from build/bin, not a path"};
  }
  return spec;
}
}  // namespace

Result<Profile> load_profile(const std::string& name_or_path, const std::string& root_dir,
                             const ConfigLookup& lookup) {
  fs::path path = name_or_path;
  if (!fs::exists(path)) path = fs::path(root_dir) / "deploy" / (name_or_path + ".yaml");
  if (!fs::exists(path)) {
    std::string known;
    for (const auto& entry : fs::directory_iterator(fs::path(root_dir) / "deploy")) {
      if (entry.path().extension() == ".yaml") {
        known += ' ';
        known += entry.path().stem().string();
      }
    }
    return Error{"profile '" + name_or_path + "' not found (known:" + known + ")"};
  }
  auto parsed = params::load_yaml_file(path.string());
  if (!parsed) return Error{parsed.error()};
  const YAML::Node& root = *parsed;
  if (!root.IsMap()) return Error{path.string() + ": expected a mapping"};
  Profile profile;
  profile.name = path.stem().string();
  for (const auto& item : root) {
    const std::string key = item.first.as<std::string>();
    if (key == "description")
      profile.description = item.second.as<std::string>();
    else if (key == "cyclonedds")
      profile.cyclonedds_config = item.second.as<std::string>();
    else if (key == "nodes") {
      if (!item.second.IsSequence()) return Error{path.string() + ": key 'nodes': expected a list"};
      std::set<std::string> names;
      for (size_t i = 0; i < item.second.size(); ++i) {
        auto node =
            parse_node(item.second[i], path.string() + ": nodes[" + std::to_string(i) + "]");
        if (!node) return Error{node.error()};
        if (!names.insert(node->name).second) {
          return Error{path.string() + ": nodes[" + std::to_string(i) + "]: duplicate name '" +
                       node->name + "'"};
        }
        profile.nodes.push_back(std::move(*node));
      }
    } else {
      return Error{path.string() + ": key '" + key +
                   "': unknown (allowed: description, cyclonedds, nodes)"};
    }
  }
  if (profile.nodes.empty()) return Error{path.string() + ": key 'nodes': missing or empty"};
  expand_root(profile, root_dir);
  if (!lookup) {
    return expand_config(std::move(profile), [&](std::string_view name) -> Result<std::string> {
      return (fs::path(root_dir) / "config" / name).string();
    });
  }
  auto expanded = expand_config(std::move(profile), lookup);
  if (!expanded) return Error{path.string() + ": " + expanded.error()};
  return expanded;
}

Result<Profile> expand_config(Profile profile, const ConfigLookup& lookup) {
  constexpr std::string_view kPrefix = "{config}/";
  auto expand = [&](std::string& s) -> Status {
    if (s.rfind(kPrefix, 0) != 0) return {};
    auto found = lookup(std::string_view(s).substr(kPrefix.size()));
    if (!found) return Error{found.error()};
    s = *found;
    return {};
  };
  if (auto e = expand(profile.cyclonedds_config); !e) return Error{"cyclonedds: " + e.error()};
  for (auto& node : profile.nodes) {
    for (auto& arg : node.args) {
      if (auto e = expand(arg); !e) return Error{"node '" + node.name + "': " + e.error()};
    }
  }
  return profile;
}

void expand_root(Profile& profile, const std::string& root_dir) {
  // Builds a new string rather than replace() in place (GCC 12 flags that with a false
  // -Wrestrict positive).
  auto expand = [&](std::string& s) {
    std::string out;
    size_t from = 0;
    for (size_t pos; (pos = s.find("{root}", from)) != std::string::npos; from = pos + 6) {
      out.append(s, from, pos - from);
      out.append(root_dir);
    }
    out.append(s, from, std::string::npos);
    s = std::move(out);
  };
  expand(profile.cyclonedds_config);
  for (auto& node : profile.nodes) {
    for (auto& arg : node.args) expand(arg);
  }
}

}  // namespace stereoball::launch
