#pragma once
// A minimal blocking WebSocket client for the viewer benchmark, as the page or as a Foxglove
// client: it reads every message on its own thread, acknowledges each image pair as the page
// does (page) or subscribes to both eyes (Foxglove), and records capture-to-receive latency.

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace stereoball::bench {

class WsClient {
 public:
  enum class Kind { kPage, kFoxglove };
  /// Connects to 127.0.0.1:port and starts reading; connected() false on failure.
  WsClient(int port, Kind kind);
  /// Closes with a close frame when clean, else just drops the TCP connection.
  ~WsClient();
  WsClient(const WsClient&) = delete;
  WsClient& operator=(const WsClient&) = delete;

  bool connected() const { return fd_ >= 0; }
  /// Image pairs (page) or left-eye images (Foxglove) received so far.
  uint64_t images() const { return images_.load(); }
  /// Capture-to-receive latencies of the images so far, ms (same host clock).
  std::vector<double> latencies_ms() const;
  /// How the destructor ends the connection (default: close frame).
  void set_clean_close(bool clean) { clean_close_ = clean; }

 private:
  void run();
  void send_text(const std::string& text);
  void on_binary(const std::vector<uint8_t>& payload);
  Kind kind_;
  int fd_ = -1;
  bool clean_close_ = true;
  std::atomic<bool> stop_{false};
  std::atomic<uint64_t> images_{0};
  mutable std::mutex mutex_;
  std::vector<double> latencies_ms_;
  std::thread thread_;
};

/// Body of GET path from 127.0.0.1:port, "" when the request failed.
std::string http_get(int port, const std::string& path);

}  // namespace stereoball::bench
