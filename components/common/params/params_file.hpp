#pragma once
// Reads a component's parameters from YAML with validation. Every key a
// component reads is required; unknown keys are errors (they are usually typos).
// Errors name the file and the key: "config/tracker.yaml: key 'ssd_threshold': ...".

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "common/util/result.hpp"

namespace stereoball::params {

class ParamsFile {
 public:
  /// Loads path; errors if unreadable, not YAML, or not a mapping at the top.
  static Result<ParamsFile> load(const std::string& path);
  /// Parses YAML text; name is used in error messages in place of a path.
  static Result<ParamsFile> parse(const std::string& text, const std::string& name);

  // Each read takes a dotted key ("rig.baseline_m"); the first problem is remembered.
  void read(std::string_view key, double& out, double min, double max);
  void read(std::string_view key, float& out, float min, float max);
  void read(std::string_view key, int& out, int min, int max);
  void read(std::string_view key, int64_t& out, int64_t min, int64_t max);
  void read(std::string_view key, uint32_t& out, uint32_t min, uint32_t max);
  void read(std::string_view key, bool& out);
  void read(std::string_view key, std::string& out);
  /// A string that must be one of choices.
  void read_choice(std::string_view key, std::string& out, const std::vector<std::string>& choices);
  /// A list of numbers; exact_size 0 = any length.
  void read(std::string_view key, std::vector<double>& out, size_t exact_size = 0);
  /// True if the key exists (marks it as known, so optional keys are not reported as unknown).
  bool has(std::string_view key);

  /// Records an error found by the caller (e.g. Params::validate()).
  void fail(const std::string& message);
  /// True once any read or fail() has recorded an error (unknown keys are found by finish()).
  bool failed() const { return !error_; }
  /// Success, or the first error, or an unknown-key error.
  Status finish() const;
  const std::string& name() const { return name_; }
  const YAML::Node& root() const { return root_; }

 private:
  ParamsFile(YAML::Node root, std::string name) : root_(std::move(root)), name_(std::move(name)) {}
  static Result<ParamsFile> from_yaml(Result<YAML::Node> root, const std::string& name);
  std::optional<YAML::Node> lookup(std::string_view key);
  std::optional<YAML::Node> scalar(std::string_view key);
  void key_error(std::string_view key, const std::string& what);
  template <typename T>
  void read_number(std::string_view key, T& out, T min, T max);

  YAML::Node root_;
  std::string name_;
  std::set<std::string, std::less<>> known_;
  Status error_;  ///< the first problem found; finish() reports it
};

}  // namespace stereoball::params
