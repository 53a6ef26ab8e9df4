#pragma once
// The viewer's web server (on WsTransport: websocketpp + asio, one thread): serves the page at /,
// its live stream to browsers over WebSocket, and the Foxglove WebSocket protocol to clients
// that ask for subprotocol foxglove.websocket.v1, all on one port. Every client has its own
// flow control (viewer/core/flow.hpp), so a slow client loses only its own frames and a stuck
// one is cut off; nothing here ever waits for a client.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "common/util/result.hpp"
#include "viewer/bridge/derived_channels.hpp"
#include "viewer/core/flow.hpp"

namespace stereoball::view {

/// Server settings.
struct ServerParams {
  std::string bind_address = "127.0.0.1";
  uint16_t port = 8765;
  viewer::FlowParams flow;
  double scene_rate_hz = 15;  ///< scene JSON pushed to browsers at most this often
};

/// Counters since start (for /stats, the tests and the benchmark).
struct ServerStats {
  uint64_t browsers = 0;           ///< connected now
  uint64_t foxglove_clients = 0;   ///< connected now
  uint64_t connections = 0;        ///< accepted since start
  uint64_t disconnected_slow = 0;  ///< cut off because they did not read
  uint64_t pairs_encoded = 0;      ///< stereo pairs JPEG-encoded (once each, for every client)
  uint64_t images_sent = 0;        ///< pairs sent, summed over clients
  uint64_t images_dropped = 0;
  uint64_t bad_client_messages = 0;
  uint64_t pairs_from_preview = 0;  ///< pairs the publisher's stereo/preview carried as JPEGs
};

/// The calibration page's hooks (stereoball view --calibrate); unset: /calibrate is 404.
struct CalibrationHooks {
  std::function<std::string()> state_json;  ///< GET /calibrate/state (any thread)
  /// The page's buttons over its WebSocket: "finish" or "write" (on the server thread).
  std::function<void(const std::string& action)> on_action;
};

class ViewServer {
 public:
  /// scene_json(now) returns the page's scene (called on the server thread, at most
  /// scene_rate_hz); plot_json() the Foxglove plot sample.
  ViewServer(const ServerParams& params, std::function<std::string(int64_t)> scene_json,
             std::function<std::string()> plot_json);
  ~ViewServer();
  ViewServer(const ViewServer&) = delete;
  ViewServer& operator=(const ViewServer&) = delete;

  /// Serves the calibration page with these hooks; before start().
  void set_calibration(CalibrationHooks hooks);

  /// Binds and starts the server thread; error names the address and the reason.
  Result<std::string> start();
  /// Stops accepting, closes every connection, joins the thread.
  void stop();

  /// Hands an encoded pair to every client that can take it (thread-safe, never blocks).
  void publish_pair(std::shared_ptr<const viewer::PairJpeg> pair);
  /// Hands derived Foxglove messages to their subscribers (thread-safe, never blocks).
  void publish_derived(std::vector<viewer::DerivedMessage> messages);
  /// True while at least one client wants images (the frame reader exists only then).
  bool images_wanted() const { return images_wanted_.load(); }
  /// Waits up to timeout_ns until some client would take an image now (a free slot, backlog
  /// under the drop limit); true when one would. The frame pump encodes only then, so frames
  /// nobody can take are skipped, never encoded and queued.
  bool wait_until_ready_for_image(int64_t timeout_ns);
  ServerStats stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::atomic<bool> images_wanted_{false};
  std::mutex ready_mutex_;
  std::condition_variable ready_changed_;
  bool ready_for_image_ = false;  // under ready_mutex_
};

}  // namespace stereoball::view
