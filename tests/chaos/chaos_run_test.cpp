// A short chaos run with real processes on a private domain: every fault kind happens once
// (nodes killed and restarted, the link cut when namespaces are available, garbage frames,
// key rotation, the e-stop, a rogue's commands) and every check of the tool passes. That an
// injected violation is caught is tested on the checks themselves (bench_chaos_checks_test).

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <sstream>
#include <string>

#include "process.hpp"

namespace sb = stereoball;
using namespace std::chrono_literals;

namespace {

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(ChaosRun, OneRoundOfEveryFaultPassesEveryCheck) {
  // Given a scratch folder and the built system (seed 1: every fault kind fits in the minute)
  const std::string dir = sb::testing::temp_dir();
  const std::string json = dir + "/chaos.json";
  // When a chaos run of one round of faults goes, ending 10 s after the last fault (at most a
  // minute; its own deadline well inside the test's)
  auto [code, output] =
      sb::testing::run({sb::testing::bin("stereoball-bench-chaos"), "--minutes", "1", "--one-round",
                        "--seed", "1", "--mean-gap", "2", "--warmup", "8", "--json", json,
                        "--out-dir", dir + "/run", "--partition", sb::testing::unique_partition()},
                       240s);
  // Then it finished, passed, and says so in its JSON
  ASSERT_NE(code, -1) << "no result within 240 s:\n" << output;
  EXPECT_EQ(code, 0) << output;
  const std::string result = read_file(json);
  ASSERT_FALSE(result.empty()) << output;
  EXPECT_NE(result.find("\"passed\": true"), std::string::npos) << result;
  // And every check ran and passed (memory growth is not judged in a minute)
  for (const char* check : {"no_motion_on_stale_or_unauthenticated_input", "estop_held",
                            "none_lost", "no_unexpected_exits", "base_log_readable"}) {
    const auto at = result.find(std::string("\"name\": \"") + check + "\", \"passed\": true");
    EXPECT_NE(at, std::string::npos) << check << " did not pass:\n" << result;
  }
  EXPECT_NE(result.find("{\"name\": \"estop_held\", \"passed\": true, \"applicable\": true"),
            std::string::npos)
      << "the e-stop was never held:\n"
      << result;
  // And every fault kind happened (the link only where namespaces are available)
  for (const char* fault :
       {"\"kill_node\"", "\"flood_frames\"", "\"rotate_key\"", "\"estop\"", "\"rogue_commands\""}) {
    EXPECT_NE(result.find(fault), std::string::npos) << fault << " missing:\n" << result;
  }
  if (result.find("\"namespaces\": true") != std::string::npos) {
    EXPECT_NE(result.find("\"cut_link\""), std::string::npos) << result;
  }
  EXPECT_NE(result.find("\"tool_failures\": 0"), std::string::npos) << output;
}

}  // namespace
