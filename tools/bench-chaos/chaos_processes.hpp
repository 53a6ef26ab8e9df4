#pragma once
// The processes of a chaos run: starting and waiting for programs, their resident memory, and
// the two network namespaces (robot, workstation) the run can cut apart.

#include <sys/types.h>

#include <csignal>
#include <cstdint>
#include <string>
#include <vector>

#include "common/node/node_runner.hpp"
#include "common/util/result.hpp"

namespace stereoball::bench_chaos {

constexpr int64_t kS = 1'000'000'000;

/// Now, ns (the node runner's clock).
inline int64_t now_ns() {
  return node::now_ns();
}

/// Set by SIGINT / SIGTERM (main.cpp): the run and the child modes stop.
extern volatile sig_atomic_t g_stop;

/// Starts argv (argv[0] a path) in its own process group with stdout and stderr appended to
/// log_path; it dies with this process. The child's pid.
pid_t spawn(const std::vector<std::string>& argv, const std::string& log_path);

// Runs argv to completion with a deadline; exit code (or -1 on timeout / failure to start).
int run_command(const std::vector<std::string>& argv, const std::string& log_path,
                int64_t timeout_ns);

// Resident memory of a process from /proc/PID/status, kB: all of it (VmRSS), and its parts:
// anonymous (heap, stacks: what a leak grows) and file-backed (code and data of the program
// and its libraries, mapped in as it first runs them).
struct Rss {
  long total_kb = -1, anon_kb = -1, file_kb = -1;
};

/// Rss of process pid (-1 where /proc does not say).
Rss read_rss(pid_t pid);

// The two "hosts": robot (simulator, recorder, e-stop, flood, rogue) and workstation
// (ball_detector, tracker, motion_controller), joined by a veth link the run can cut.
struct Namespaces {
  std::string ip;
  std::string robot, workstation, robot_iface, ws_iface, robot_addr, ws_addr;
  bool created = false;

  /// Creates both namespaces and the veth pair between them; an error names the failing step.
  Status make();
  /// Takes the link down or brings it up; false when ip failed.
  bool set_link(bool up) const;
  ~Namespaces();
};

}  // namespace stereoball::bench_chaos
