#include "viewer_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <thread>
#include <vector>

extern char** environ;

namespace stereoball::demo {

ViewerProcess::ViewerProcess(const std::string& bin_dir, int domain, const std::string& partition,
                             const std::string& bind, int port, const std::string& log_path) {
  const std::vector<std::string> args = {bin_dir + "/stereoball-view",
                                         "--domain",
                                         std::to_string(domain),
                                         "--partition",
                                         partition,
                                         "--bind",
                                         bind,
                                         "--port",
                                         std::to_string(port)};
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_path.c_str(),
                                   O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  const int rc = posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) {
    pid_ = -1;
    error_ = "cannot start " + args[0] + ": " + std::strerror(rc);
    return;
  }
  // A busy port makes the viewer exit at once: report that instead of a dead address.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  int status = 0;
  if (waitpid(pid_, &status, WNOHANG) == pid_) {
    pid_ = -1;
    error_ =
        "the viewer exited at start (port " + std::to_string(port) + " busy?), see " + log_path;
  }
}

ViewerProcess::~ViewerProcess() {
  if (pid_ <= 0) return;
  kill(pid_, SIGTERM);
  for (int i = 0; i < 50; ++i) {
    if (waitpid(pid_, nullptr, WNOHANG) == pid_) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  kill(pid_, SIGKILL);
  waitpid(pid_, nullptr, 0);
}

}  // namespace stereoball::demo
