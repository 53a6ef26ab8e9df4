// A third network namespace, "rogue", joined to the robot's namespace by its own link: not on
// the robot's Cyclone interface, not in its peer list. With the robot and workstation
// profiles running (deployment key on both hosts) and the operator's stop engaged, the rogue
// sends unsigned, forged (its own key) and replayed (captured from the deployment) commands,
// tracks, detections, e-stop releases and calibrations. Discovery lets it in (its writers
// match the robot's readers); authentication keeps it out: the robot does not move and the
// stop stays engaged. Skipped with the reason without root/iproute2.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <thread>

#include "common/node/node_runner.hpp"
#include "two_host_system.hpp"

namespace sb = stereoball;
namespace sd = stereoball::distributed;
using namespace std::chrono_literals;

namespace {

// Newest ground truth the robot namespace received, if any.
std::optional<sd::TruthRx> newest_truth(sd::TwoHostSystem& system) {
  const auto log = system.robot_log();
  if (log.truths.empty()) return std::nullopt;
  return log.truths.back();
}

unsigned matched_readers(const std::string& output) {
  const auto at = output.find("rogue: matched ");
  return at == std::string::npos ? 0 : std::stoul(output.substr(at + 15));
}

}  // namespace

TEST(RogueHost, ThirdNamespaceMovesNothingAndClearsNoStop) {
  sd::SystemOptions o;
  o.domain = sb::testing::test_domain();
  o.partition = sb::testing::unique_partition();
  o.robot_observer_topics = {"truth"};
  o.rogue_host = true;
  sd::TwoHostSystem system(o);
  if (auto e = system.start(); !e) {
    if (system.unavailable()) GTEST_SKIP() << e.error();
    FAIL() << e.error();
  }
  const std::vector<std::string> where{"--domain", std::to_string(o.domain), "--partition",
                                       o.partition};
  auto with = [&](std::vector<std::string> argv) {
    argv.insert(argv.end(), where.begin(), where.end());
    return argv;
  };
  ASSERT_TRUE(sb::testing::eventually([&] { return newest_truth(system).has_value(); }, 40s))
      << system.diagnostics();

  // Given the operator's stop, engaged from the workstation, and the robot at rest
  auto [code, output] = system.run_tool(
      system.hosts().workstation(),
      with({sb::testing::bin("stereoball-estop"), "engage", "--wait", "20"}), system.key_file());
  ASSERT_EQ(code, 0) << output << system.diagnostics();
  // Only ground truth received well after the stop counts: a command the controller sent just
  // before it still drives the base until the zero after it arrives, and the newest samples
  // the observer holds when the tool returns may predate that (one CI run saw 1.4 mm of motion
  // after a "rest" taken at once; not reproduced in 7 runs since). The base's command timeout
  // (300 ms) bounds how long any earlier command can act.
  const std::int64_t settled_ns = sb::node::now_ns() + 500'000'000;
  ASSERT_TRUE(sb::testing::eventually(
      [&] {
        const auto log = system.robot_log();
        if (log.truths.size() < 10 || log.truths[log.truths.size() - 10].rx_ns <= settled_ns)
          return false;
        // At rest in both: a robot searching when the stop came still turns while its
        // angular speed ramps down, after its linear speed is already 0.
        for (size_t i = log.truths.size() - 10; i < log.truths.size(); ++i) {
          if (std::abs(log.truths[i].linear_mps) > 1e-6) return false;
          if (std::abs(log.truths[i].angular_radps) > 1e-6) return false;
        }
        return true;
      },
      20s))
      << "the robot did not come to rest after the stop";
  const sd::TruthRx rest = *newest_truth(system);

  // When the rogue namespace attacks
  const std::string rogue_key = sb::testing::make_key_file(sb::testing::temp_dir(), "rogue.key");
  ASSERT_FALSE(::testing::Test::HasFailure()) << "no rogue key";
  const auto& rogue = system.hosts().rogue();
  auto& replay = system.start_in(rogue,
                                 with({sb::testing::bin("sb_rogue"), "--attack", "replay",
                                       "--capture", "4", "--duration", "6"}),
                                 rogue_key);
  auto& unsigned_rogue = system.start_in(
      rogue, with({sb::testing::bin("sb_rogue"), "--attack", "unsigned", "--duration", "8"}),
      rogue_key);
  auto& forged = system.start_in(
      rogue, with({sb::testing::bin("sb_rogue"), "--attack", "forged", "--duration", "8"}),
      rogue_key);
  for (sb::testing::Process* p : {&replay, &unsigned_rogue, &forged}) {
    const auto exit = p->wait_for_exit(60s);
    ASSERT_TRUE(exit.has_value()) << p->output();
    EXPECT_EQ(*exit, 0) << p->output();
  }
  // Ground truth must cover the time after the last attack in which a command could still
  // act (the base's command timeout is 300 ms): wait for a sample received 500 ms after it.
  // Measured: such a sample arrived 1.37-1.59 s after the attackers exited (3 runs, shared
  // 2-core machine while compiling); the deadline is 10 s.
  const std::int64_t attacks_over_ns = sb::node::now_ns() + 500'000'000;
  ASSERT_TRUE(sb::testing::eventually(
      [&] {
        const auto truth = newest_truth(system);
        return truth && truth->rx_ns > attacks_over_ns;
      },
      10s))
      << system.diagnostics();

  // Then the rogue was discovered and matched (the peer list did not keep it out)
  EXPECT_GT(matched_readers(unsigned_rogue.output()), 0u) << unsigned_rogue.output();
  EXPECT_GT(matched_readers(forged.output()), 0u) << forged.output();
  EXPECT_EQ(replay.output().find("rogue: captured 0"), std::string::npos) << replay.output();
  // And the robot never moved
  double moved_m = 0;
  for (const auto& g : system.robot_log().truths) {
    if (g.rx_ns <= rest.rx_ns) continue;
    moved_m =
        std::max(moved_m, std::hypot(g.robot_x_m - rest.robot_x_m, g.robot_y_m - rest.robot_y_m));
    moved_m = std::max(moved_m, std::abs(g.robot_yaw_rad - rest.robot_yaw_rad));
  }
  EXPECT_LT(moved_m, 1e-3);
  // And the stop is still engaged, as the robot sees it
  auto [sc, status] =
      system.run_tool(system.hosts().robot(),
                      with({sb::testing::bin("stereoball-estop"), "status"}), system.key_file());
  EXPECT_EQ(sc, 0) << status;
  EXPECT_NE(status.find("state: ENGAGED"), std::string::npos) << status;
}
