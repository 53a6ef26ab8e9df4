#include "viewer_process.hpp"

#include <chrono>
#include <thread>
#include <vector>

namespace stereoball::demo {

ViewerProcess::ViewerProcess(const std::string& bin_dir, int domain, const std::string& partition,
                             const std::string& bind, int port, const std::string& log_path)
    : child_(std::make_unique<view_client::Child>(
          std::vector<std::string>{bin_dir + "/stereoball-view", "--domain", std::to_string(domain),
                                   "--partition", partition, "--bind", bind, "--port",
                                   std::to_string(port)},
          log_path)) {
  if (!child_->error().empty()) {
    error_ = child_->error();
    return;
  }
  // A busy port makes the viewer exit at once: report that instead of a dead address.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  if (!child_->running())
    error_ =
        "the viewer exited at start (port " + std::to_string(port) + " busy?), see " + log_path;
}

}  // namespace stereoball::demo
