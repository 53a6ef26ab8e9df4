// Tools reach the deployment they belong to (issue 39, item 7): the operator's stop, run as a
// separate program with no DDS configuration of its own, reaches the nodes that
// `stereoball launch all-in-one` started with a deployment key (the profile gives them
// config/cyclonedds/loopback.xml; before the tools resolved the deployment's configuration the
// tool used Cyclone's defaults and reached 0 readers).

#include <gtest/gtest.h>
#include <signal.h>

#include <map>
#include <regex>
#include <string>

#include "common/dds/reader.hpp"
#include "common/node/node_runner.hpp"
#include "process.hpp"

namespace sb = stereoball;
using namespace std::chrono_literals;

namespace {

// The environment of an operator's shell: no DDS configuration, no profile or interface, no
// settings file of an installed role (the host's must not decide the test).
std::vector<std::string> operator_shell(const std::vector<std::string>& argv) {
  std::vector<std::string> cmd{"/usr/bin/env",         "-u", "CYCLONEDDS_URI",   "-u",
                               "STEREOBALL_PROFILE",   "-u", "STEREOBALL_IFACE", "-u",
                               "STEREOBALL_CONFIG_DIR"};
  cmd.insert(cmd.end(), argv.begin(), argv.end());
  return cmd;
}

// The newest value of a counter in each component's health/status.
class Health {
 public:
  explicit Health(sb::dds::DomainParticipant& participant)
      : reader_(participant, sb::topics::kComponentStatus) {}
  void drain() {
    for (auto& s : reader_.take(256)) {
      auto& counters = latest_[s->component];
      counters.clear();
      for (uint32_t i = 0; i < s->counters._length; ++i) {
        counters[s->counters._buffer[i].name] = s->counters._buffer[i].value;
      }
    }
  }
  bool seen(const std::string& component) {
    drain();
    return latest_.count(component) > 0;
  }
  uint64_t counter(const std::string& component, const std::string& name) {
    drain();
    auto& counters = latest_[component];
    auto it = counters.find(name);
    return it == counters.end() ? 0 : it->second;
  }

 private:
  sb::dds::DataReader<stereoball_msg_ComponentStatus> reader_;
  std::map<std::string, std::map<std::string, uint64_t>> latest_;
};

}  // namespace

// Given `stereoball launch all-in-one` running with a deployment key on a private domain and
// partition, when the operator runs `stereoball estop engage` in another shell where
// CYCLONEDDS_URI is not set, then the tool names the DDS configuration it used (the profile's
// loopback.xml), reports the stop delivered to the nodes that hold it, exits 0, and both
// holders (the simulator's base and the motion controller) report the stop engaged.
TEST(DeploymentDds, EstopFromAnotherShellReachesTheLaunchedAllInOne) {
  const std::string dir = sb::testing::temp_dir();
  const std::string key = sb::testing::make_key_file(dir, "deployment.key");
  const std::string domain = std::to_string(sb::testing::test_domain());
  const std::string partition = sb::testing::unique_partition();
  const std::vector<std::string> deployment_env{"STEREOBALL_KEY_FILE=" + key,
                                                "STEREOBALL_ENV_FILE="};
  auto launcher = sb::testing::Process::start(
      operator_shell({sb::testing::bin("stereoball"), "launch", "all-in-one", "--domain", domain,
                      "--partition", partition, "--log", dir + "/nodes.log", "--duration", "120"}),
      deployment_env);
  // The observer uses the test's loopback configuration (ctest), the same file as the nodes.
  sb::dds::DomainParticipant observer({sb::testing::test_domain(), partition, key});
  Health health(observer);
  ASSERT_TRUE(sb::testing::eventually(
      [&] { return health.seen("simulator") && health.seen("motion_controller"); }, 60s))
      << launcher.output();
  ASSERT_EQ(health.counter("simulator", "estop_engaged"), 0u);

  const auto [code, output] =
      sb::testing::run(operator_shell({sb::testing::bin("stereoball"), "estop", "engage",
                                       "--reason", "deployment test", "--domain", domain,
                                       "--partition", partition, "--wait", "10"}),
                       60s, deployment_env);

  EXPECT_EQ(code, 0) << output;
  EXPECT_NE(output.find("DDS configuration: file://"), std::string::npos) << output;
  EXPECT_NE(output.find("cyclonedds/loopback.xml (profile all-in-one"), std::string::npos)
      << output;
  std::smatch readers;
  ASSERT_TRUE(std::regex_search(output, readers, std::regex("delivered to ([0-9]+) reader")))
      << output;
  EXPECT_GE(std::stoi(readers[1]), 2) << output;
  for (const char* holder : {"simulator", "motion_controller"}) {
    EXPECT_TRUE(
        sb::testing::eventually([&] { return health.counter(holder, "estop_engaged") == 1; }, 15s))
        << holder << " did not get the stop\n"
        << output;
  }
  launcher.signal(SIGTERM);
  EXPECT_TRUE(launcher.wait_for_exit(20s).has_value());
}
