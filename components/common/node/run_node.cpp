#include "common/node/run_node.hpp"

#include "common/util/cli11.hpp"

#include <cstdio>
#include <exception>

#include "common/util/log.hpp"

namespace stereoball::node {

int run_node(int argc, char** argv, const NodeMain& node, const NodeConfigure& configure) {
  block_termination_signals();
  CLI::App app{node.description};
  CommonOptions common;
  add_common_flags(app, common, node.config_file);
  add_help_params(app, node.param_specs);
  if (node.add_flags) node.add_flags(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  // Before the parameters load, so whatever loading logs carries the node's name.
  log::Level level = log::Level::kInfo;
  log::parse_level(common.log_level, level);
  log::init(node.name, level);
  const auto fail = [&node](const std::string& message, int code) {
    std::fprintf(stderr, "%s: %s\n", node.name.c_str(), message.c_str());
    return code;
  };
  // Outlives the node: what it captured (the parameters) may be referenced by it.
  const auto build = configure(common);
  if (!build) return fail(build.error(), 2);
  try {
    Runner runner(node.name, common);
    // Declared after the runner, so destroyed before it.
    const auto built = (*build)(runner);
    if (!built) return fail(built.error(), 2);
    return runner.run();
  } catch (const std::exception& e) {
    return fail(e.what(), 1);
  }
}

}  // namespace stereoball::node
