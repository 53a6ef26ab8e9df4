#pragma once
// The WebSocket + HTTP transport of the viewer: websocketpp on standalone asio, one thread.
// Kept apart, and compiled as C++17, because websocketpp 0.8.2 (Debian bookworm) does not
// compile as C++20; this header uses nothing newer than C++17. Connections are numbered;
// every callback and every send/terminate runs on the transport's own thread (use post()).

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace stereoball::view {

/// Reply to a plain HTTP request.
struct HttpReply {
  int status = 200;
  std::string content_type;
  std::string body;
};

class WsTransport {
 public:
  struct Handlers {
    std::function<void(uint64_t id, const std::string& subprotocol)> on_open;
    std::function<void(uint64_t id)> on_close;
    std::function<void(uint64_t id, bool text, const std::string& payload)> on_message;
    std::function<HttpReply(const std::string& resource)> on_http;
  };
  /// subprotocols: the ones this server selects when a client offers them.
  WsTransport(Handlers handlers, std::vector<std::string> subprotocols, size_t max_incoming_bytes);
  ~WsTransport();
  WsTransport(const WsTransport&) = delete;
  WsTransport& operator=(const WsTransport&) = delete;

  /// Binds bind_address:port and starts the thread; "" on success, else the reason. The
  /// port actually bound (port 0 = any free one) goes to bound_port.
  std::string start(const std::string& bind_address, uint16_t port, uint16_t& bound_port);
  /// Closes every connection and joins the thread.
  void stop();
  /// Runs fn on the transport thread (thread-safe).
  void post(std::function<void()> fn);
  /// Calls fn on the transport thread every period_ns until stop().
  void every(int64_t period_ns, std::function<void()> fn);

  // Transport thread only:
  /// Queues a message; false when the connection is gone.
  bool send(uint64_t id, const void* data, size_t size, bool binary);
  /// Bytes queued for the connection and not yet handed to the socket.
  size_t queued_bytes(uint64_t id) const;
  /// Drops the connection at once (no close handshake: for clients that do not read).
  void terminate(uint64_t id);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace stereoball::view
