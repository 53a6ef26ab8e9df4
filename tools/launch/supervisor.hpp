#pragma once
// Supervisor: starts the nodes of a profile as separate processes, restarts crashed ones
// with back-off, and stops them all (SIGTERM, then SIGKILL after a grace period).

#include <sys/types.h>

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "profile.hpp"

namespace stereoball::launch {

struct SupervisorOptions {
  std::string bin_dir;                  ///< where the node programs are
  std::string log_path;                 ///< every node's stdout/stderr is appended here
  std::vector<std::string> extra_args;  ///< appended to every node (e.g. --domain N)
  std::map<std::string, std::vector<std::string>> node_args;  ///< appended per node name
  int max_restarts = 5;                   ///< per node; then it stays down (reported)
  int64_t stop_grace_ns = 3'000'000'000;  ///< SIGTERM -> SIGKILL delay
};

/// What happened to a node, for the console and for tests.
struct NodeState {
  std::string name;
  pid_t pid = -1;  ///< -1 when not running
  int restarts = 0;
  int last_exit_code = 0;  ///< 128+signal if killed by a signal
  bool given_up = false;
  bool skipped = false;  ///< optional node whose program is not built
};

class Supervisor {
 public:
  using EventSink = std::function<void(const std::string&)>;
  Supervisor(Profile profile, SupervisorOptions options, EventSink events);
  ~Supervisor();
  /// Starts every node; returns an error naming a required program that is not built.
  Result<bool> start_all(int64_t now_ns);
  /// Reaps exited nodes and restarts them when due; call every ~100 ms.
  void poll(int64_t now_ns);
  /// Stops every node: SIGTERM, waits up to the grace period, then SIGKILL. Returns true if
  /// every node exited by itself with code 0.
  bool stop_all();
  const std::vector<NodeState>& states() const { return states_; }
  /// Sends sig to a node (tests and tools).
  void signal_node(const std::string& name, int sig);

 private:
  pid_t spawn(const NodeSpec& spec);
  Profile profile_;
  SupervisorOptions options_;
  EventSink events_;
  std::vector<NodeState> states_;
  std::vector<int64_t> restart_due_ns_;
  int log_fd_ = -1;
};

}  // namespace stereoball::launch
