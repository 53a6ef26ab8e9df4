// Supervisor and `stereoball launch`: real node processes, restarts, clean stop.

#include <gtest/gtest.h>
#include <signal.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "common/node/node_runner.hpp"
#include "process.hpp"
#include "profile.hpp"
#include "supervisor.hpp"

namespace sb = stereoball;
using namespace std::chrono_literals;

namespace {

std::string write_profile(const std::string& dir, const std::string& body) {
  const std::string path = dir + "/profile.yaml";
  std::ofstream(path) << body;
  return path;
}

const char* kTwoPeers = R"(description: two test peers
nodes:
  - name: first
    program: sb_test_peer
    args: ["echo", "ball/track", "--config", "{root}/tests/foundation/test_peer.yaml"]
  - name: second
    program: sb_test_peer
    args: ["echo", "ball/detection", "--config", "{root}/tests/foundation/test_peer.yaml"]
)";

// Polls the supervisor until its first node runs again under another pid than old_pid.
bool first_node_restarted(sb::launch::Supervisor& supervisor, pid_t old_pid) {
  return sb::testing::eventually(
      [&] {
        supervisor.poll(sb::node::monotonic_ns());
        return supervisor.states()[0].pid > 0 && supervisor.states()[0].pid != old_pid;
      },
      10s);
}

// Whether process pid has blocked SIGTERM (/proc/PID/status, SigBlk). A node does so first
// thing in main; from then on SIGTERM stops it cleanly (exit 0) instead of killing it.
bool blocks_sigterm(pid_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("SigBlk:", 0) != 0) continue;
    const unsigned long long mask = std::stoull(line.substr(7), nullptr, 16);
    return (mask >> (SIGTERM - 1)) & 1;
  }
  return false;
}

// Waits until every node of the supervisor runs and has blocked SIGTERM. Measured: 35-155 ms
// (20 waits in 5 runs, shared 2-core machine while compiling); the deadline is 10 s.
bool all_nodes_ready(sb::launch::Supervisor& supervisor) {
  return sb::testing::eventually(
      [&] {
        supervisor.poll(sb::node::monotonic_ns());
        for (const auto& st : supervisor.states()) {
          if (st.pid <= 0 || !blocks_sigterm(st.pid)) return false;
        }
        return true;
      },
      10s);
}

sb::launch::SupervisorOptions options(const std::string& dir) {
  sb::launch::SupervisorOptions o;
  o.bin_dir = sb::testing::bin("").substr(0, sb::testing::bin("").size() - 1);
  o.log_path = dir + "/nodes.log";
  o.extra_args = {"--domain", std::to_string(sb::testing::test_domain()), "--partition",
                  sb::testing::unique_partition()};
  return o;
}

TEST(Profile, RepositoryProfilesAllLoad) {
  for (const char* name : {"all-in-one", "robot", "workstation", "robot-cameras"}) {
    auto p = sb::launch::load_profile(name, SB_SOURCE_DIR);
    ASSERT_TRUE(p) << name << ": " << p.error();
    EXPECT_FALSE(p->nodes.empty());
    EXPECT_EQ(p->cyclonedds_config.find("{root}"), std::string::npos);
  }
}

TEST(Profile, BadProfilesNameTheProblem) {
  const std::string dir = sb::testing::temp_dir();
  struct Case {
    std::string body, expected;
  };
  const std::vector<Case> cases = {
      {"nodes:\n  - name: a\n    program: x\n    colour: red\n", "nodes[0]: key 'colour': unknown"},
      {"nodes:\n  - name: a\n    program: x\n  - name: a\n    program: y\n", "duplicate name 'a'"},
      {"nodes:\n  - name: a\n", "key 'program': missing"},
      {"description: none\n", "key 'nodes': missing or empty"},
      {"nodes: [\n", "not valid YAML"},
      {"description: a\nnodes:\n  - name: a\n    program: x\ndescription: b\n",
       "key 'description' appears twice (lines 1 and 5)"},
  };
  for (const auto& c : cases) {
    auto p = sb::launch::load_profile(write_profile(dir, c.body), SB_SOURCE_DIR);
    ASSERT_FALSE(p) << c.body;
    EXPECT_NE(p.error().find(c.expected), std::string::npos) << p.error();
  }
  auto missing = sb::launch::load_profile("no-such-profile", SB_SOURCE_DIR);
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().find("all-in-one"), std::string::npos) << "lists the known profiles";
}

// Given two supervised nodes, when one is killed, then it is restarted with a new pid,
// and stopping the profile ends both cleanly (exit 0 on SIGTERM).
TEST(Supervisor, RestartsACrashedNodeAndStopsAllCleanly) {
  const std::string dir = sb::testing::temp_dir();
  auto profile = sb::launch::load_profile(write_profile(dir, kTwoPeers), SB_SOURCE_DIR);
  ASSERT_TRUE(profile) << profile.error();
  std::vector<std::string> events;
  sb::launch::Supervisor supervisor(*profile, options(dir),
                                    [&](const std::string& e) { events.push_back(e); });
  ASSERT_TRUE(supervisor.start_all(sb::node::monotonic_ns()));
  ASSERT_TRUE(all_nodes_ready(supervisor));
  const pid_t first_pid = supervisor.states()[0].pid;
  ASSERT_GT(first_pid, 0);
  supervisor.signal_node("first", SIGKILL);
  ASSERT_TRUE(first_node_restarted(supervisor, first_pid)) << "not restarted";
  EXPECT_EQ(supervisor.states()[0].restarts, 1);
  EXPECT_EQ(supervisor.states()[0].last_exit_code, 128 + SIGKILL);
  EXPECT_EQ(supervisor.states()[1].restarts, 0);
  ASSERT_TRUE(all_nodes_ready(supervisor));  // the new first node can stop cleanly
  EXPECT_TRUE(supervisor.stop_all());
  for (const auto& st : supervisor.states()) {
    EXPECT_EQ(st.pid, -1);
    EXPECT_EQ(st.last_exit_code, 0) << st.name;
  }
}

// Given two supervised nodes, when one is stopped from outside with SIGTERM (it exits 0), then
// it is restarted all the same: only the launcher decides that a node stays down.
TEST(Supervisor, RestartsANodeThatExitsCleanlyWhenNotStoppedByTheLauncher) {
  const std::string dir = sb::testing::temp_dir();
  auto profile = sb::launch::load_profile(write_profile(dir, kTwoPeers), SB_SOURCE_DIR);
  ASSERT_TRUE(profile) << profile.error();
  std::vector<std::string> events;
  sb::launch::Supervisor supervisor(*profile, options(dir),
                                    [&](const std::string& e) { events.push_back(e); });
  ASSERT_TRUE(supervisor.start_all(sb::node::monotonic_ns()));
  ASSERT_TRUE(all_nodes_ready(supervisor));  // so SIGTERM ends it with exit code 0
  const pid_t first_pid = supervisor.states()[0].pid;
  supervisor.signal_node("first", SIGTERM);
  ASSERT_TRUE(first_node_restarted(supervisor, first_pid)) << "not restarted";
  EXPECT_EQ(supervisor.states()[0].last_exit_code, 0);
  bool logged = false;
  for (const auto& e : events)
    logged |= e.find("first: exited with code 0, restarting in 500 ms") != std::string::npos;
  EXPECT_TRUE(logged);
  ASSERT_TRUE(all_nodes_ready(supervisor));  // the new node has blocked SIGTERM
  EXPECT_TRUE(supervisor.stop_all());
}

// Given a node that exits at once every time, then it is restarted with a doubling back-off
// until the limit, then left down with a log line saying so.
TEST(Supervisor, GivesUpAfterTheRestartLimitWithDoublingBackoff) {
  const std::string dir = sb::testing::temp_dir();
  auto profile =
      sb::launch::load_profile(write_profile(dir,
                                             "nodes:\n  - name: broken\n    program: sb_test_peer\n"
                                             "    args: [\"--config\", \"/no/such/file.yaml\"]\n"),
                               SB_SOURCE_DIR);
  ASSERT_TRUE(profile) << profile.error();
  auto o = options(dir);
  o.max_restarts = 3;
  o.restart_backoff_ns = 20'000'000;
  std::vector<std::string> events;
  sb::launch::Supervisor supervisor(*profile, o,
                                    [&](const std::string& e) { events.push_back(e); });
  ASSERT_TRUE(supervisor.start_all(sb::node::monotonic_ns()));
  ASSERT_TRUE(sb::testing::eventually(
      [&] {
        supervisor.poll(sb::node::monotonic_ns());
        return supervisor.states()[0].given_up;
      },
      20s));
  EXPECT_EQ(supervisor.states()[0].restarts, 3);
  std::string all;
  for (const auto& e : events) all += e + "\n";
  for (const char* delay : {"restarting in 20 ms", "restarting in 40 ms", "restarting in 80 ms",
                            "gave up after 3 restarts in a row"}) {
    EXPECT_NE(all.find(delay), std::string::npos) << all;
  }
}

bool process_gone(pid_t pid) {
  // A killed node reparented to a PID 1 that does not reap stays a zombie: that is gone too.
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(stat)), {});
  const auto close = text.rfind(')');
  return text.empty() || (close != std::string::npos && text.size() > close + 2 &&
                          (text[close + 2] == 'Z' || text[close + 2] == 'X'));
}

std::vector<pid_t> started_pids(const std::string& output) {
  std::vector<pid_t> pids;
  for (size_t at = output.find("started (pid "); at != std::string::npos;
       at = output.find("started (pid ", at + 1)) {
    pids.push_back(static_cast<pid_t>(std::stol(output.substr(at + 13))));
  }
  return pids;
}

// Given `stereoball launch` running two nodes, when the launcher is killed with SIGKILL (no
// chance to clean up), then both nodes die too.
TEST(LaunchCommand, SigkillOfTheLauncherTakesItsNodesDown) {
  const std::string dir = sb::testing::temp_dir();
  auto launch = sb::testing::Process::start(
      {sb::testing::bin("stereoball-launch"), write_profile(dir, kTwoPeers), "--log",
       dir + "/nodes.log", "--domain", std::to_string(sb::testing::test_domain()), "--partition",
       sb::testing::unique_partition()});
  ASSERT_TRUE(launch.wait_for_output("second: started", 10s)) << launch.output();
  const auto pids = started_pids(launch.output());
  ASSERT_EQ(pids.size(), 2u) << launch.output();
  for (pid_t pid : pids) ASSERT_FALSE(process_gone(pid));
  launch.signal(SIGKILL);
  ASSERT_TRUE(launch.wait_for_exit(10s).has_value());
  for (pid_t pid : pids) {
    EXPECT_TRUE(sb::testing::eventually([&] { return process_gone(pid); }, 10s))
        << "node " << pid << " outlived its launcher";
  }
}

// Given `stereoball launch` running a profile, when it gets SIGTERM, then it exits 0 and
// takes its nodes down with it.
TEST(LaunchCommand, SigtermStopsEveryNode) {
  const std::string dir = sb::testing::temp_dir();
  const std::string path = write_profile(dir, kTwoPeers);
  auto launch = sb::testing::Process::start(
      {sb::testing::bin("stereoball-launch"), path, "--log", dir + "/nodes.log", "--domain",
       std::to_string(sb::testing::test_domain()), "--partition", sb::testing::unique_partition()});
  ASSERT_TRUE(launch.wait_for_output("second: started", 10s)) << launch.output();
  ASSERT_TRUE(sb::testing::eventually(
      [&] {
        std::ifstream in(dir + "/nodes.log");
        std::string text((std::istreambuf_iterator<char>(in)), {});
        return text.find("echoing ball/detection") != std::string::npos;
      },
      10s));
  launch.signal(SIGTERM);
  const auto code = launch.wait_for_exit(10s);
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 0) << launch.output();
  EXPECT_NE(launch.output().find("all nodes stopped cleanly"), std::string::npos)
      << launch.output();
}

}  // namespace
