#pragma once
// Test support: start real processes, wait for them with deadlines, read their output.

#include <sys/types.h>

#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace stereoball::testing {

/// A child process whose stdout and stderr go to a temporary file. Killed (SIGKILL) and
/// reaped on destruction if still running, so a failing test never leaks processes.
class Process {
 public:
  /// Starts argv[0] (a path) with argv; extra_env entries "K=V" are added to the environment.
  static Process start(const std::vector<std::string>& argv,
                       const std::vector<std::string>& extra_env = {});
  ~Process();
  Process(Process&& other) noexcept;
  Process& operator=(Process&&) = delete;
  Process(const Process&) = delete;

  pid_t pid() const { return pid_; }
  bool running();
  void signal(int sig);
  /// Exit code (or 128+signal if killed by a signal), or nullopt if still running at the deadline.
  std::optional<int> wait_for_exit(std::chrono::milliseconds timeout);
  /// Everything the process printed so far (stdout and stderr interleaved).
  std::string output() const;
  /// Waits until output() contains text; false at the deadline.
  bool wait_for_output(const std::string& text, std::chrono::milliseconds timeout) const;

 private:
  Process(pid_t pid, std::string log_path) : pid_(pid), log_path_(std::move(log_path)) {}
  pid_t pid_ = -1;
  std::string log_path_;
  std::optional<int> exit_code_;
};

/// Runs argv to completion (deadline timeout); returns {exit code or -1 on timeout, output}.
std::pair<int, std::string> run(const std::vector<std::string>& argv,
                                std::chrono::milliseconds timeout,
                                const std::vector<std::string>& extra_env = {});

/// Path of a built program in build/bin.
std::string bin(const std::string& name);
/// Path of a file in the source tree.
std::string source_path(const std::string& relative);
/// This test binary's DDS domain (from STEREOBALL_DOMAIN, set by ctest).
int test_domain();
/// A partition name unique to the running test (test suite + name + pid).
std::string unique_partition();
/// Polls pred every 10 ms until true or timeout; returns pred's last value.
bool eventually(const std::function<bool()>& pred, std::chrono::milliseconds timeout);
/// A memory figure of a running process from /proc/PID/status in kB, e.g. "VmHWM" (peak
/// resident set) or "VmRSS"; nullopt when the process or the field is gone.
std::optional<long> memory_kb(pid_t pid, const std::string& field);
/// A fresh empty temporary directory.
std::string temp_dir();
/// Creates a deployment key dir/name with `stereoball-keys init` and returns its path; a
/// failure of the tool fails the running test (with the tool's output) and still returns it.
std::string make_key_file(const std::string& dir, const std::string& name);

}  // namespace stereoball::testing
