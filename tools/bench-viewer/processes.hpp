#pragma once
// Processes the viewer benchmark starts and watches: spawning with output to a log, CPU time
// and resident memory from /proc, a process's children, the load average.

#include <sys/types.h>

#include <optional>
#include <regex>
#include <string>
#include <vector>

namespace stereoball::bench {

/// CPU seconds (user + system) a process has used so far; nullopt when it is gone.
std::optional<double> cpu_seconds(pid_t pid);
/// Resident memory of a process, MB; nullopt when it is gone.
std::optional<double> rss_mb(pid_t pid);
/// Direct children of a process.
std::vector<pid_t> children_of(pid_t pid);
/// 1-minute load average of the host.
double load_average();

/// A child process, stopped (SIGTERM, then SIGKILL after 5 s) when destroyed.
class Child {
 public:
  /// Starts argv with stdout and stderr appended to log_path; pid() -1 on failure.
  Child(const std::vector<std::string>& argv, const std::string& log_path);
  ~Child();
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  pid_t pid() const { return pid_; }
  bool running();
  /// Waits up to timeout_s for pattern in the log; its first group, or nullopt.
  std::optional<std::string> wait_for_log(const std::regex& pattern, double timeout_s);

 private:
  pid_t pid_ = -1;
  std::string log_path_;
};

/// Program `name` beside this executable (the build's bin/ or the installed libexec/).
std::string sibling_program(const std::string& name);

}  // namespace stereoball::bench
