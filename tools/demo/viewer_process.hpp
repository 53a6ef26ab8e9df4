#pragma once
// `stereoball demo --view`: the viewer (stereoball-view) as a child process for the whole
// demo, subscribed to every scenario's partition, stopped when the demo ends.

#include <memory>
#include <string>

#include "child_process.hpp"

namespace stereoball::demo {

class ViewerProcess {
 public:
  /// Starts bin_dir/stereoball-view on domain, partition pattern, bind address and port;
  /// its output goes to log_path. error() says why when it could not start.
  ViewerProcess(const std::string& bin_dir, int domain, const std::string& partition,
                const std::string& bind, int port, const std::string& log_path);
  bool running() const { return child_ && child_->pid() > 0; }
  const std::string& error() const { return error_; }

 private:
  std::unique_ptr<view_client::Child> child_;
  std::string error_;
};

}  // namespace stereoball::demo
