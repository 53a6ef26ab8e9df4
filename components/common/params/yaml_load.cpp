#include "common/params/yaml_load.hpp"

#include <fstream>
#include <sstream>
#include <unordered_map>

namespace stereoball::params {
namespace {

std::string key_text(const YAML::Node& key) {
  return key.IsScalar() ? key.Scalar() : YAML::Dump(key);
}

std::string child_path(const std::string& prefix, const std::string& part) {
  return prefix.empty() ? part : prefix + "." + part;
}

// Depth-first search; the recursion depth is bounded by yaml-cpp's own nesting limit.
Status check_in(const YAML::Node& node, const std::string& prefix) {
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) {
      if (auto st = check_in(node[i], prefix + "[" + std::to_string(i) + "]"); !st) return st;
    }
  }
  if (!node.IsMap()) return {};
  std::unordered_map<std::string, int> line_of;  // key -> its 1-based line
  for (const auto& item : node) {
    const std::string key = key_text(item.first);
    const int line = item.first.Mark().line + 1;
    const auto [first, inserted] = line_of.emplace(key, line);
    if (!inserted) {
      return Error{"key '" + child_path(prefix, key) + "' appears twice (lines " +
                   std::to_string(first->second) + " and " + std::to_string(line) + ")"};
    }
    if (auto st = check_in(item.second, child_path(prefix, key)); !st) return st;
  }
  return {};
}

}  // namespace

Status check_unique_keys(const YAML::Node& root) {
  return check_in(root, "");
}

Result<YAML::Node> parse_yaml(const std::string& text, const std::string& name) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    return Error{name + ": not valid YAML: " + e.what()};
  }
  if (auto st = check_unique_keys(root); !st) return Error{name + ": " + st.error()};
  return root;
}

Result<YAML::Node> load_yaml_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{path + ": cannot read file"};
  std::stringstream text;
  text << in.rdbuf();
  if (in.bad()) return Error{path + ": cannot read file"};
  return parse_yaml(text.str(), path);
}

}  // namespace stereoball::params
