// `NODE --help-params` of each of the five nodes: exit 0 with no config file to be found, and
// print exactly the generated table of the node's README.

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <string>

#include "process.hpp"

namespace sb = stereoball;

namespace {

using namespace std::chrono_literals;

std::string readme_table(const std::string& readme) {
  std::ifstream in(sb::testing::source_path(readme));
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  const std::string begin = "<!-- params:begin -->\n";
  const auto from = s.find(begin);
  const auto to = s.find("<!-- params:end -->");
  if (from == std::string::npos || to == std::string::npos) return "(no markers in " + readme + ")";
  return s.substr(from + begin.size(), to - from - begin.size());
}

TEST(ParamsHelp, GivenEachNodeWhenAskedForItsParametersThenPrintsItsReadmeTableWithoutAnyFile) {
  const std::pair<const char*, const char*> nodes[] = {
      {"tracker", "components/tracker/README.md"},
      {"motion_controller", "components/motion_controller/README.md"},
      {"camera_server", "components/camera_server/README.md"},
      {"simulator", "components/simulator/README.md"},
      {"ball_detector", "components/ball_detector/node/README.md"},
  };
  for (const auto& [node, readme] : nodes) {
    // Given no config file anywhere the search order looks
    const auto [code, out] = sb::testing::run({sb::testing::bin(node), "--help-params"}, 20s,
                                              {"STEREOBALL_CONFIG_DIR=/nonexistent"});
    // Then the table is printed and the node exits 0
    EXPECT_EQ(code, 0) << node << ": " << out;
    EXPECT_EQ(out, readme_table(readme)) << node;
  }
}

}  // namespace
