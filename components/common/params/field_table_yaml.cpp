#include "common/params/field_table_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <limits>

namespace stereoball::params {
namespace {

// Reads one typed value through ParamsFile, which records missing keys and type errors.
template <typename T, typename... Args>
std::optional<Value> read_as(ParamsFile& file, const std::string& key, Args&&... args) {
  T out{};
  file.read(key, out, std::forward<Args>(args)...);
  if (file.failed()) return std::nullopt;
  return Value{std::move(out)};
}

// The mapping under root at the dotted key's parent, created on the way.
YAML::Node parent_of(YAML::Node root, const std::string& key, std::string& leaf) {
  YAML::Node node = root;
  std::size_t start = 0;
  for (std::size_t dot = key.find('.'); dot != std::string::npos; dot = key.find('.', start)) {
    const std::string part = key.substr(start, dot - start);
    YAML::Node child = node[part];
    node.reset(child);
    start = dot + 1;
  }
  leaf = key.substr(start);
  return node;
}

}  // namespace

std::optional<Value> read_value(ParamsFile& file, const FieldSpec& spec) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  switch (spec.kind) {
    case Kind::kBool:
      return read_as<bool>(file, spec.key);
    case Kind::kInt:
      return read_as<std::int64_t>(file, spec.key, std::numeric_limits<std::int64_t>::lowest(),
                                   std::numeric_limits<std::int64_t>::max());
    case Kind::kReal:
      return read_as<double>(file, spec.key, -kInf, kInf);
    case Kind::kText:
      return read_as<std::string>(file, spec.key);
    case Kind::kChoice: {
      std::string word;
      file.read(spec.key, word);
      if (file.failed()) return std::nullopt;
      return Value{word};  // check_value names the allowed words
    }
    case Kind::kList:
      return read_as<std::vector<double>>(file, spec.key, spec.list_size);
  }
  return std::nullopt;
}

std::string yaml_text(const std::vector<std::pair<std::string, Value>>& values) {
  YAML::Node root(YAML::NodeType::Map);
  for (const auto& [key, value] : values) {
    std::string leaf;
    YAML::Node parent = parent_of(root, key, leaf);
    if (const auto* list = std::get_if<std::vector<double>>(&value)) {
      YAML::Node seq(YAML::NodeType::Sequence);
      seq.SetStyle(YAML::EmitterStyle::Flow);
      for (double x : *list) seq.push_back(value_text(x));
      parent[leaf] = seq;
    } else {
      parent[leaf] = value_text(value);
    }
  }
  YAML::Emitter out;
  out << root;
  return std::string(out.c_str()) + "\n";
}

}  // namespace stereoball::params
