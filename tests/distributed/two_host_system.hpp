#pragma once
// The whole system on two namespace "hosts": `stereoball launch robot` in one, `stereoball
// launch workstation` in the other (LAN Cyclone configuration, unicast peers), and observers.
// Shared by the two-host test and the distributed benchmark.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/util/result.hpp"
#include "observer_log.hpp"
#include "process.hpp"
#include "two_hosts.hpp"

namespace stereoball::distributed {

/// A process stopped gently (SIGTERM, then SIGKILL after grace) when it goes out of scope.
class GentleProcess {
 public:
  explicit GentleProcess(testing::Process process) : process_(std::move(process)) {}
  ~GentleProcess();
  GentleProcess(const GentleProcess&) = delete;
  GentleProcess& operator=(const GentleProcess&) = delete;
  testing::Process& get() { return process_; }

 private:
  testing::Process process_;
};

/// Which deploy/ profile runs in which namespace, on which domain and partition.
struct SystemOptions {
  int domain = 0;
  std::string partition;
  std::string robot_profile = "robot";
  std::string workstation_profile = "workstation";
  std::vector<std::string> robot_observer_topics{"truth", "track", "cmd"};
  std::vector<std::string> workstation_observer_topics{};  ///< empty: no observer there
  bool rogue_host = false;  ///< also create the third, "rogue" namespace (TwoHosts::add_rogue)
};

/// Robot and workstation profiles running in two namespaces, plus observers. Stops
/// everything and removes the namespaces when destroyed.
class TwoHostSystem {
 public:
  explicit TwoHostSystem(SystemOptions options);
  ~TwoHostSystem();
  /// Creates the hosts and starts observers and both launchers; error = skip reason or failure.
  Status start();
  TwoHosts& hosts() { return hosts_; }
  /// What the observer in the robot namespace has received so far.
  ObserverLog robot_log() const;
  /// What the observer in the workstation namespace has received so far.
  ObserverLog workstation_log() const;
  /// Tail of both launchers' node logs (for failure messages).
  std::string diagnostics() const;
  /// Program names (/proc/PID/comm) running in host's namespace.
  std::vector<std::string> programs(const Host& host) const;
  /// Whether namespaces could not be created (then start() returned the reason).
  bool unavailable() const { return unavailable_; }
  /// The deployment key file both hosts use (made by start()).
  const std::string& key_file() const { return key_file_; }
  /// Runs a StereoBall tool in host's namespace with the LAN configuration, to completion.
  std::pair<int, std::string> run_tool(const Host& host, const std::vector<std::string>& argv,
                                       const std::string& key_file) const;
  /// Starts a program in host's namespace with the LAN configuration (stopped with the rest).
  testing::Process& start_in(const Host& host, const std::vector<std::string>& argv,
                             const std::string& key_file);

 private:
  SystemOptions options_;
  TwoHosts hosts_;
  std::string dir_;
  std::string key_file_;
  bool unavailable_ = false;
  // Declared after hosts_: destroyed first, so nodes stop before the namespaces go.
  std::vector<std::unique_ptr<GentleProcess>> processes_;
  GentleProcess* robot_observer_ = nullptr;
  GentleProcess* workstation_observer_ = nullptr;
};

/// Linear interpolation percentile (p in [0, 100]) of values; 0 for none.
double percentile(std::vector<double> values, double p);

}  // namespace stereoball::distributed
