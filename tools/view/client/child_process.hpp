#pragma once
// `stereoball view` (or any program) as a child process of a tool or test: started with its
// output appended to a log, watched through that log, stopped (SIGTERM, then SIGKILL after
// 5 s) when the handle goes away.

#include <sys/types.h>

#include <optional>
#include <regex>
#include <string>
#include <vector>

namespace stereoball::view_client {

class Child {
 public:
  /// Starts argv[0] with argv, stdout and stderr appended to log_path; error() says why not.
  Child(const std::vector<std::string>& argv, const std::string& log_path);
  ~Child();
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  /// -1 when it could not start or has exited (and was reaped).
  pid_t pid() const { return pid_; }
  bool running();
  const std::string& error() const { return error_; }
  /// Waits up to timeout_s for pattern in the log; its first group (or the whole match), or
  /// nullopt when it did not appear or the child exited.
  std::optional<std::string> wait_for_log(const std::regex& pattern, double timeout_s);

 private:
  pid_t pid_ = -1;
  std::string log_path_;
  std::string error_;
};

/// Program `name` beside this executable (the build's bin/ or the installed libexec/).
std::string sibling_program(const std::string& name);

}  // namespace stereoball::view_client
