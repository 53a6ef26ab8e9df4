#include "common/params/params_file.hpp"

#include "common/params/yaml_load.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace stereoball::params {
namespace {

std::vector<std::string> split_key(std::string_view key) {
  std::vector<std::string> parts;
  size_t start = 0;
  while (start <= key.size()) {
    const size_t dot = key.find('.', start);
    const size_t end = dot == std::string_view::npos ? key.size() : dot;
    parts.emplace_back(key.substr(start, end - start));
    start = end + 1;
  }
  return parts;
}

// Collects every leaf key of a mapping as a dotted path.
void collect_leaf_keys(const YAML::Node& node, const std::string& prefix,
                       std::vector<std::string>& out) {
  if (!node.IsMap()) {
    out.push_back(prefix);
    return;
  }
  for (const auto& item : node) {
    const std::string key = item.first.as<std::string>();
    collect_leaf_keys(item.second, prefix.empty() ? key : prefix + "." + key, out);
  }
}

template <typename T>
std::string number_text(T value) {
  std::ostringstream os;
  os << value;
  return os.str();
}

}  // namespace

Result<ParamsFile> ParamsFile::load(const std::string& path) {
  return from_yaml(load_yaml_file(path), path);
}

Result<ParamsFile> ParamsFile::parse(const std::string& text, const std::string& name) {
  return from_yaml(parse_yaml(text, name), name);
}

Result<ParamsFile> ParamsFile::from_yaml(Result<YAML::Node> root, const std::string& name) {
  if (!root) return Error{root.error()};
  if (!root->IsMap()) return Error{name + ": expected a mapping of parameters at the top level"};
  return ParamsFile(*root, name);
}

std::optional<YAML::Node> ParamsFile::lookup(std::string_view key) {
  known_.insert(std::string(key));
  // Index through const references: yaml-cpp's non-const operator[] inserts missing keys,
  // and assigning one Node to another overwrites the referenced node (hence reset()).
  YAML::Node walk;
  walk.reset(root_);
  for (const auto& part : split_key(key)) {
    if (!walk.IsMap()) return std::nullopt;
    const YAML::Node& const_walk = walk;
    YAML::Node child = const_walk[part];
    if (!child.IsDefined() || child.IsNull()) return std::nullopt;
    walk.reset(child);
  }
  return walk;
}

void ParamsFile::key_error(std::string_view key, const std::string& what) {
  if (error_) error_ = Error{name_ + ": key '" + std::string(key) + "': " + what};
}

void ParamsFile::fail(const std::string& message) {
  if (error_) error_ = Error{name_ + ": " + message};
}

std::optional<YAML::Node> ParamsFile::scalar(std::string_view key) {
  auto node = lookup(key);
  if (!node) {
    key_error(key, "missing");
    return std::nullopt;
  }
  if (!node->IsScalar()) {
    key_error(key, "expected a single value, got a list or mapping");
    return std::nullopt;
  }
  return node;
}

template <typename T>
void ParamsFile::read_number(std::string_view key, T& out, T min, T max) {
  auto node = scalar(key);
  if (!node) return;
  const std::string text = node->Scalar();
  T value{};
  try {
    if constexpr (std::is_floating_point_v<T>) {
      size_t used = 0;
      const double parsed = std::stod(text, &used);
      if (used != text.size() || !std::isfinite(parsed)) throw std::invalid_argument(text);
      value = static_cast<T>(parsed);
    } else {
      size_t used = 0;
      const long long parsed = std::stoll(text, &used);
      if (used != text.size()) throw std::invalid_argument(text);
      if (parsed < static_cast<long long>(std::numeric_limits<T>::min()) ||
          parsed > static_cast<long long>(std::numeric_limits<T>::max())) {
        throw std::out_of_range(text);
      }
      value = static_cast<T>(parsed);
    }
  } catch (const std::exception&) {
    key_error(key, std::string("expected ") +
                       (std::is_floating_point_v<T> ? "a number" : "an integer") + ", got '" +
                       text + "'");
    return;
  }
  if (value < min || value > max) {
    key_error(key, number_text(value) + " is out of range [" + number_text(min) + ", " +
                       number_text(max) + "]");
    return;
  }
  out = value;
}

void ParamsFile::read(std::string_view key, double& out, double min, double max) {
  read_number(key, out, min, max);
}
void ParamsFile::read(std::string_view key, float& out, float min, float max) {
  read_number(key, out, min, max);
}
void ParamsFile::read(std::string_view key, int& out, int min, int max) {
  read_number(key, out, min, max);
}
void ParamsFile::read(std::string_view key, int64_t& out, int64_t min, int64_t max) {
  read_number(key, out, min, max);
}
void ParamsFile::read(std::string_view key, uint32_t& out, uint32_t min, uint32_t max) {
  read_number(key, out, min, max);
}

void ParamsFile::read(std::string_view key, bool& out) {
  auto node = scalar(key);
  if (!node) return;
  const std::string text = node->Scalar();
  if (text == "true" || text == "yes" || text == "on")
    out = true;
  else if (text == "false" || text == "no" || text == "off")
    out = false;
  else
    key_error(key, "expected true or false, got '" + text + "'");
}

void ParamsFile::read(std::string_view key, std::string& out) {
  auto node = scalar(key);
  if (node) out = node->Scalar();
}

void ParamsFile::read_choice(std::string_view key, std::string& out,
                             const std::vector<std::string>& choices) {
  auto node = scalar(key);
  if (!node) return;
  const std::string text = node->Scalar();
  for (const auto& choice : choices) {
    if (choice == text) {
      out = text;
      return;
    }
  }
  std::string allowed;
  for (const auto& choice : choices) allowed += (allowed.empty() ? "" : ", ") + choice;
  key_error(key, "'" + text + "' is not one of: " + allowed);
}

void ParamsFile::read(std::string_view key, std::vector<double>& out, size_t exact_size) {
  auto node = lookup(key);
  if (!node) return key_error(key, "missing");
  if (!node->IsSequence()) return key_error(key, "expected a list of numbers");
  if (exact_size && node->size() != exact_size) {
    return key_error(key, "expected " + std::to_string(exact_size) + " numbers, got " +
                              std::to_string(node->size()));
  }
  std::vector<double> values;
  for (const auto& item : *node) {
    try {
      values.push_back(item.as<double>());
    } catch (const YAML::Exception&) {
      return key_error(key, "expected a list of numbers");
    }
  }
  out = std::move(values);
}

bool ParamsFile::has(std::string_view key) {
  return lookup(key).has_value();
}

Status ParamsFile::finish() const {
  if (!error_) return error_;
  std::vector<std::string> leaves;
  collect_leaf_keys(root_, "", leaves);
  for (const auto& leaf : leaves) {
    // A leaf is known if it was read, or lies under a key that was read as a whole.
    bool known = false;
    for (const auto& k : known_) {
      if (leaf == k || leaf.rfind(k + ".", 0) == 0) known = true;
    }
    if (!known) return Error{name_ + ": key '" + leaf + "': unknown parameter"};
  }
  return {};
}

}  // namespace stereoball::params
