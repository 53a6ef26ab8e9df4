#pragma once
// Processes the viewer benchmark watches: CPU time and resident memory from /proc, a
// process's children, the load average (starting them: tools/view/client/child_process.hpp).

#include <sys/types.h>

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "child_process.hpp"

namespace stereoball::bench {

using view_client::Child;
using view_client::sibling_program;

/// CPU seconds (user + system) a process has used so far; nullopt when it is gone.
std::optional<double> cpu_seconds(pid_t pid);
/// CPU seconds per thread name of a process (threads of the same name summed).
std::map<std::string, double> thread_cpu_seconds(pid_t pid);
/// Resident memory of a process, MB; nullopt when it is gone.
std::optional<double> rss_mb(pid_t pid);
/// The command name of a process (/proc/PID/comm), "?" when it is gone.
std::string process_name(pid_t pid);
/// Direct children of a process.
std::vector<pid_t> children_of(pid_t pid);
/// 1-minute load average of the host.
double load_average();

}  // namespace stereoball::bench
