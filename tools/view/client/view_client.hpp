#pragma once
// Clients of `stereoball view` for its tests and its benchmark: plain HTTP GET, the WebSocket
// handshake and client frames, and a reader that behaves like the page (acknowledges each pair
// it "draws") or like a Foxglove client (subscribes to both eyes), recording per pair when it
// was captured, taken and encoded by the viewer, and received. Blocking sockets on 127.0.0.1.

#include <atomic>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "viewer/core/pair_message.hpp"

namespace stereoball::view_client {

/// A TCP connection to 127.0.0.1:port whose receives time out after recv_timeout_ms; -1 when
/// refused.
int tcp_connect(int port, int recv_timeout_ms);
/// Sends all of bytes (MSG_NOSIGNAL: a closed peer is not a signal).
void send_all(int fd, const std::string& bytes);
/// True when response holds its head and the whole body its Content-Length announces.
bool http_response_complete(const std::string& response);
/// Body of GET path from 127.0.0.1:port ("" when the request failed or took over 5 s).
std::string http_get(int port, const std::string& path);
/// One counter of the viewer's /stats, -1 when unavailable.
long stats_counter(int port, const std::string& name);

/// Opens a WebSocket (optionally asking for a subprotocol); -1 unless the server said 101.
int ws_connect(int port, const std::string& subprotocol = "", int recv_timeout_ms = 10'000);
/// A client frame: FIN + opcode, masked (mask 0 keeps the payload readable), any length.
std::string client_frame(uint8_t opcode, const std::string& payload, bool masked = true);
/// Reads n bytes, retrying on the socket's receive timeout until stop; false when the
/// connection ended (or stop was set).
bool read_exact(int fd, void* out, size_t n, const std::atomic<bool>& stop);
/// Reads one (unfragmented) server message into opcode and payload; false as read_exact.
bool read_message(int fd, uint8_t& opcode, std::vector<uint8_t>& payload,
                  const std::atomic<bool>& stop);

/// Where the time of one image went, ms (same host clock for every stamp).
struct PairTiming {
  double capture_to_taken = 0;     ///< capture -> the viewer took the frame from DDS
  double taken_to_encoded = 0;     ///< -> both eyes encoded
  double encoded_to_received = 0;  ///< -> this client received the message
  double capture_to_received = 0;  ///< the whole way
};

/// A WebSocket client on its own reading thread.
class WsClient {
 public:
  enum class Kind { kPage, kFoxglove };
  /// Connects to 127.0.0.1:port as kind and starts reading; connected() false on failure. A
  /// page client acknowledges each pair when it arrives unless acks is false.
  WsClient(int port, Kind kind, bool acks = true);
  /// Closes with a close frame when clean, else just drops the TCP connection.
  ~WsClient();
  WsClient(const WsClient&) = delete;
  WsClient& operator=(const WsClient&) = delete;

  bool connected() const { return fd_ >= 0; }
  /// Image pairs (page) or left-eye images (Foxglove) received so far.
  uint64_t images() const { return images_.load(); }
  /// Timings of the images so far (the viewer's stages only for page clients).
  std::vector<PairTiming> timings() const;
  /// Capture-to-receive latencies so far, ms.
  std::vector<double> latencies_ms() const;
  /// Header of the last pair a page client received.
  std::optional<viewer::PairHeader> last_pair() const;
  /// Sends one acknowledgement (for a page client that does not ack by itself).
  void ack();
  /// How the destructor ends the connection (default: close frame).
  void set_clean_close(bool clean) { clean_close_ = clean; }

 private:
  void run();
  void on_binary(const std::vector<uint8_t>& payload);
  Kind kind_;
  bool acks_;
  int fd_ = -1;
  bool clean_close_ = true;
  std::atomic<bool> stop_{false};
  std::atomic<uint64_t> images_{0};
  mutable std::mutex mutex_;
  std::vector<PairTiming> timings_;
  std::optional<viewer::PairHeader> last_pair_;
  std::thread thread_;
};

}  // namespace stereoball::view_client
