#pragma once
// Supervisor: starts the nodes of a profile as separate processes, restarts every node that
// exits while the supervisor is not stopping it (crash, error, or a clean exit after a stray
// SIGTERM) with back-off and a limit, and stops them all (SIGTERM, then SIGKILL after a grace
// period). Each node gets SIGTERM from the kernel when the supervisor dies, even by SIGKILL
// (PR_SET_PDEATHSIG), so no node outlives its launcher.

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
  int max_restarts = 5;  ///< restarts in a row per node; then it stays down (reported)
  int64_t restart_backoff_ns = 500'000'000;  ///< first restart delay; doubles each time
  int64_t max_backoff_ns = 8'000'000'000;    ///< the delay stops doubling here
  /// A node that ran this long before exiting has its restart count and back-off reset.
  int64_t stable_after_ns = 60'000'000'000;
  int64_t stop_grace_ns = 3'000'000'000;  ///< SIGTERM -> SIGKILL delay
};

/// What happened to a node, for the console and for tests.
struct NodeState {
  std::string name;
  pid_t pid = -1;           ///< -1 when not running
  int restarts = 0;         ///< restarts since the launch
  int restarts_in_row = 0;  ///< restarts without a stable run between them
  int last_exit_code = 0;   ///< 128+signal if killed by a signal
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
  void on_exit(size_t i, int status, int64_t now_ns);
  Profile profile_;
  SupervisorOptions options_;
  EventSink events_;
  std::vector<NodeState> states_;
  std::vector<int64_t> restart_due_ns_;
  std::vector<int64_t> started_ns_;  // when each node was last (re)started
  int log_fd_ = -1;
};

}  // namespace stereoball::launch
