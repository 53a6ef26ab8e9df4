// Smoke test of stereoball-bench-closed-loop: the real tool on a few simulated seconds of the
// plain still-ball scenario and of the no-ball scenario prints the table and writes sane JSON;
// bad input gives one clear error line and exit code 2.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <fstream>
#include <sstream>
#include <string>

#include "process.hpp"

namespace st = stereoball::testing;
using namespace std::chrono_literals;

namespace {

const nlohmann::json* find_scenario(const nlohmann::json& j, const std::string& name) {
  for (const auto& s : j.at("scenarios"))
    if (s.at("name") == name) return &s;
  return nullptr;
}

void expect_fraction(const nlohmann::json& value, const std::string& what) {
  ASSERT_TRUE(value.is_number()) << what << " = " << value;
  EXPECT_GE(value.get<double>(), 0.0) << what;
  EXPECT_LE(value.get<double>(), 1.0) << what;
}

}  // namespace

TEST(BenchClosedLoopTool, StillPlainBallAndNoBallGiveSaneFigures) {
  // Given the tool on 4 s of the plain still ball (1.5 m ahead at the start) and 4 s of the
  // clutter-only scene, one seed each
  const std::string json_path = st::temp_dir() + "/closed_loop.json";
  const auto [code, out] =
      st::run({st::bin("stereoball-bench-closed-loop"), "--scenario", "ball_still_plain",
               "--scenario", "no_ball", "--seconds", "4", "--seeds", "1", "--json", json_path},
              100s);
  ASSERT_EQ(code, 0) << out;
  // Then the table has a row per scenario, a total row and the definitions
  EXPECT_NE(out.find("Definitions"), std::string::npos) << out;
  EXPECT_NE(out.find("\nball_still_plain "), std::string::npos) << out;
  EXPECT_NE(out.find("\nno_ball "), std::string::npos) << out;
  EXPECT_NE(out.find("\nTOTAL "), std::string::npos) << out;
  std::ifstream in(json_path);
  ASSERT_TRUE(in.good()) << "no JSON written\n" << out;
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << "JSON does not parse";
  const auto* still = find_scenario(j, "ball_still_plain");
  const auto* none = find_scenario(j, "no_ball");
  ASSERT_TRUE(still && none) << j.dump(2);
  // And the still ball was reachable after the settling time and the robot, driving from
  // 1.5 m to the 1 m target, kept it within tolerance for most of that time
  const auto& a = still->at("a");
  EXPECT_GT(a.at("reachable_s").get<double>(), 1.0) << a;
  for (const char* f :
       {"kept_fraction", "distance_ok_fraction", "bearing_ok_fraction", "following_fraction"})
    expect_fraction(a.at(f), f);
  EXPECT_GT(a.at("kept_fraction").get<double>(), 0.5) << a;
  expect_fraction(still->at("detection_rate"), "detection_rate");
  // And with no ball there is nothing reachable and the track never follows
  EXPECT_EQ(none->at("a").at("reachable_s").get<double>(), 0.0);
  EXPECT_EQ(none->at("c").at("no_ball_runs").get<int>(), 1);
  EXPECT_EQ(none->at("c").at("ok_runs").get<int>(), 1);
  EXPECT_EQ(none->at("c").at("longest_following_s").get<double>(), 0.0);
  // And the total counts both runs
  EXPECT_EQ(j.at("total").at("runs").get<int>(), 2);
  EXPECT_EQ(j.at("runs").size(), 2u);
}

TEST(BenchClosedLoopTool, UnknownScenarioIsOneClearErrorWithExitCode2) {
  // Given a scenario name that has no file
  const auto [code, out] =
      st::run({st::bin("stereoball-bench-closed-loop"), "--scenario", "no_such_scenario"}, 30s);
  // Then the tool exits with 2 and one line naming the scenario
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("no_such_scenario"), std::string::npos) << out;
  EXPECT_EQ(out.find('\n'), out.size() - 1) << "expected a single line:\n" << out;
}

TEST(BenchClosedLoopTool, BadFlagValueIsRejected) {
  // Given zero seeds, Then the value is rejected with exit code 2, naming the flag
  const auto [code, out] = st::run({st::bin("stereoball-bench-closed-loop"), "--seeds", "0"}, 30s);
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("--seeds"), std::string::npos) << out;
}

TEST(BenchClosedLoopTool, RunsSideBySideGiveTheFiguresOfRunsOneAfterAnother) {
  // Given two scenarios with two seeds each, 3 simulated seconds
  const auto run = [](const char* jobs) {
    return st::run({st::bin("stereoball-bench-closed-loop"), "--scenario", "ball_still_plain",
                    "--scenario", "no_ball", "--seconds", "3", "--seeds", "2", "--jobs", jobs},
                   100s);
  };
  // When they run one after another and two at a time, Then the reports are the same
  const auto [code1, one] = run("1");
  const auto [code2, two] = run("2");
  ASSERT_EQ(code1, 0) << one;
  ASSERT_EQ(code2, 0) << two;
  // (but for the progress lines, whose wall times and order differ)
  const auto report = [](const std::string& out) {
    std::istringstream in(out);
    std::string line, kept;
    while (std::getline(in, line))
      if (line.find(" frames in ") == std::string::npos) kept += line + "\n";
    return kept;
  };
  EXPECT_NE(one.find("\nTOTAL "), std::string::npos) << one;
  EXPECT_EQ(report(one), report(two));
}
