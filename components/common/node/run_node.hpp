#pragma once
// run_node: the whole main() of a node. Parses the common flags (and the node's own), loads
// the parameters, builds the node on a Runner and runs it until SIGINT/SIGTERM (exit 0).
// A configuration error (parameters, flags, files) prints "<name>: <error>" and exits 2; an
// exception while building or running prints "<name>: <what>" and exits 1.

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "common/node/common_flags.hpp"
#include "common/node/node_runner.hpp"
#include "common/params/field_table.hpp"
#include "common/util/result.hpp"

// Declared only: CLI/CLI.hpp costs seconds of compile time in every file that includes it; the
// files that add flags include it themselves.
namespace CLI {
class App;
}  // namespace CLI

namespace stereoball::node {

/// What tells one node's command line from another's.
struct NodeMain {
  std::string name;                            ///< component name ("tracker"): logs, errors
  std::string description;                     ///< the --help text
  std::string config_file;                     ///< parameters file searched ("tracker.yaml")
  std::vector<params::FieldSpec> param_specs;  ///< what --help-params prints
  /// Adds the node's own flags (after the common ones and --help-params); {} for none.
  std::function<void(CLI::App&)> add_flags;
};

/// A built node of any type, kept alive while the runner runs.
using NodeHandle = std::shared_ptr<void>;
/// Builds the node on the runner; an Error is a configuration error (exit 2).
using NodeBuilder = std::function<Result<NodeHandle>(Runner&)>;
/// After parsing: loads the parameters (options.config_path) and checks the node's own flags;
/// returns how to build the node, or the configuration error (exit 2).
using NodeConfigure = std::function<Result<NodeBuilder>(const CommonOptions&)>;

/// Runs a node's main() (see the file comment); returns the process exit code.
int run_node(int argc, char** argv, const NodeMain& node, const NodeConfigure& configure);

/// The same with the two steps typed: load(options) -> Result<Config> reads the parameters and
/// checks the node's own flags; build(runner, config) -> Result<NodeHandle> (or a NodeHandle)
/// builds the node. Config must be copyable.
template <typename Load, typename Build>
int run_node(int argc, char** argv, const NodeMain& node, Load load, Build build) {
  return run_node(
      argc, argv, node, [&load, &build](const CommonOptions& common) -> Result<NodeBuilder> {
        auto config = load(common);
        if (!config) return Error{config.error()};
        return NodeBuilder([&build, config = std::move(config).value()](Runner& runner) {
          return build(runner, config);
        });
      });
}

/// The usual node: parameters from load(config path), then Node(runner, params).
template <typename Node, typename Params>
int run_node(int argc, char** argv, const NodeMain& node,
             Result<Params> (*load)(const std::string& path)) {
  return run_node(
      argc, argv, node, [load](const CommonOptions& common) { return load(common.config_path); },
      [](Runner& runner, const Params& params) {
        return NodeHandle(std::make_shared<Node>(runner, params));
      });
}

}  // namespace stereoball::node
