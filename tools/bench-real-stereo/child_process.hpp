#pragma once
// A node started by the bench: its output goes to a log file, every wait has a deadline, and
// it is always stopped and reaped (SIGINT, then SIGKILL) when the owner goes, also on errors.
// The child asks the kernel for SIGTERM should the bench itself die first.

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "common/util/result.hpp"

namespace stereoball::real_stereo {

/// One child process.
class ChildProcess {
 public:
  /// Starts argv[0] (a path) with argv, stdout and stderr appended to log_path.
  static Result<ChildProcess> start(const std::vector<std::string>& argv,
                                    const std::string& log_path);
  ~ChildProcess();
  ChildProcess(ChildProcess&& other) noexcept;
  ChildProcess& operator=(ChildProcess&&) = delete;
  ChildProcess(const ChildProcess&) = delete;

  /// Whether it still runs (reaps it if it ended).
  bool running();
  /// Exit code (128 + signal when killed), once it has ended.
  std::optional<int> exit_code() const { return exit_code_; }
  /// SIGINT, wait up to grace, then SIGKILL and reap; the exit code.
  int stop(std::chrono::milliseconds grace);
  /// The last max_lines lines of its log.
  std::string log_tail(std::size_t max_lines) const;
  /// Whether its log contains text.
  bool log_contains(const std::string& text) const;
  const std::string& log_path() const { return log_path_; }
  const std::string& name() const { return name_; }

 private:
  ChildProcess(pid_t pid, std::string name, std::string log_path)
      : pid_(pid), name_(std::move(name)), log_path_(std::move(log_path)) {}
  pid_t pid_ = -1;
  std::string name_;
  std::string log_path_;
  std::optional<int> exit_code_;
};

}  // namespace stereoball::real_stereo
