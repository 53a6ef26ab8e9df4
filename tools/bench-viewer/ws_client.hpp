#pragma once
// A minimal blocking WebSocket client for the viewer benchmark: it behaves like the page
// (reads every message, acknowledges each image pair) and records image latency.

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace stereoball::bench {

class PageClient {
 public:
  /// Connects to 127.0.0.1:port and starts reading; connected() false on failure.
  explicit PageClient(int port);
  ~PageClient();
  bool connected() const { return fd_ >= 0; }
  uint64_t images() const { return images_.load(); }
  /// Capture-to-receive latencies of the images so far, ms (same host clock).
  std::vector<double> latencies_ms() const;

 private:
  void run();
  int fd_ = -1;
  std::atomic<bool> stop_{false};
  std::atomic<uint64_t> images_{0};
  mutable std::mutex mutex_;
  std::vector<double> latencies_ms_;
  std::thread thread_;
};

}  // namespace stereoball::bench
