#include "ws_client.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

namespace stereoball::bench {
namespace {

// Foxglove channels 1 and 2 are the left and right eye (view/left/image, view/right/image).
constexpr char kSubscribeEyes[] =
    R"({"op":"subscribe","subscriptions":[{"id":1,"channelId":1},{"id":2,"channelId":2}]})";

// Reads n bytes; false when the connection ended or stop was set (timeouts just retry).
bool read_exact(int fd, void* out, size_t n, const std::atomic<bool>& stop) {
  auto* p = static_cast<uint8_t*>(out);
  while (n > 0) {
    const ssize_t r = recv(fd, p, n, 0);
    if (r < 0 && (errno == EAGAIN || errno == EWOULDBLOCK) && !stop) continue;
    if (r <= 0) return false;
    p += r;
    n -= static_cast<size_t>(r);
  }
  return true;
}

double now_ms() {
  return std::chrono::duration<double, std::milli>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// A client frame (clients must mask; the zero key leaves the payload as it is).
std::string client_frame(uint8_t opcode, const std::string& payload) {
  std::string f(1, static_cast<char>(0x80 | opcode));
  if (payload.size() < 126) {
    f += static_cast<char>(0x80 | payload.size());
  } else {
    f += static_cast<char>(0x80 | 126);
    f += static_cast<char>(payload.size() >> 8);
    f += static_cast<char>(payload.size() & 0xff);
  }
  return f + std::string(4, '\0') + payload;
}

int connect_local(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  // A short timeout lets a reader notice that it should stop while the server sends nothing.
  timeval tv{0, 200'000};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) return fd;
  close(fd);
  return -1;
}

}  // namespace

std::string http_get(int port, const std::string& path) {
  const int fd = connect_local(port);
  if (fd < 0) return "";
  const std::string request = "GET " + path + " HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n";
  std::string response;
  if (send(fd, request.data(), request.size(), MSG_NOSIGNAL) > 0) {
    char buf[4096];
    // The server keeps the connection open: stop once the body (Content-Length) is in.
    auto complete = [&response] {
      const auto head = response.find("\r\n\r\n");
      const auto length = response.find("Content-Length: ");
      return head != std::string::npos && length != std::string::npos && length < head &&
             response.size() - head - 4 >= std::stoul(response.substr(length + 16));
    };
    for (int timeouts = 0; timeouts < 25 && !complete();) {
      const ssize_t n = recv(fd, buf, sizeof buf, 0);
      if (n > 0) {
        response.append(buf, static_cast<size_t>(n));
      } else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
        ++timeouts;
      } else {
        break;
      }
    }
  }
  close(fd);
  const auto body = response.find("\r\n\r\n");
  return body == std::string::npos ? "" : response.substr(body + 4);
}

WsClient::WsClient(int port, Kind kind) : kind_(kind) {
  fd_ = connect_local(port);
  if (fd_ < 0) return;
  const std::string hello =
      "GET / HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
      "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n" +
      std::string(kind == Kind::kFoxglove ? "Sec-WebSocket-Protocol: foxglove.websocket.v1\r\n"
                                          : "") +
      "\r\n";
  std::string head;
  char c;
  if (send(fd_, hello.data(), hello.size(), MSG_NOSIGNAL) > 0) {
    for (int timeouts = 0; head.find("\r\n\r\n") == std::string::npos && timeouts < 50;) {
      if (recv(fd_, &c, 1, 0) == 1) {
        head += c;
      } else if (errno == EAGAIN || errno == EWOULDBLOCK) {
        ++timeouts;
      } else {
        break;
      }
    }
  }
  if (head.rfind("HTTP/1.1 101", 0) != 0) {
    close(fd_);
    fd_ = -1;
    return;
  }
  if (kind_ == Kind::kFoxglove) send_text(kSubscribeEyes);
  thread_ = std::thread([this] { run(); });
}

WsClient::~WsClient() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  if (fd_ < 0) return;
  if (clean_close_) {
    const std::string close_frame = client_frame(0x8, std::string("\x03\xe8", 2));  // 1000
    send(fd_, close_frame.data(), close_frame.size(), MSG_NOSIGNAL);
  }
  close(fd_);
}

std::vector<double> WsClient::latencies_ms() const {
  std::lock_guard lock(mutex_);
  return latencies_ms_;
}

void WsClient::send_text(const std::string& text) {
  const std::string frame = client_frame(0x1, text);
  send(fd_, frame.data(), frame.size(), MSG_NOSIGNAL);
}

void WsClient::on_binary(const std::vector<uint8_t>& payload) {
  double capture_ms = 0;
  if (kind_ == Kind::kPage) {
    // type u32 = 1, left length u32, seq f64, capture ms f64, JPEGs
    uint32_t type = 0;
    if (payload.size() < 24) return;
    std::memcpy(&type, payload.data(), 4);
    if (type != 1) return;
    std::memcpy(&capture_ms, payload.data() + 16, 8);
    send_text("ack");
  } else {
    // Message Data: opcode 1, subscription id u32, log time u64 ns (the capture time), data
    uint32_t subscription = 0;
    uint64_t stamp_ns = 0;
    if (payload.size() < 13 || payload[0] != 1) return;
    std::memcpy(&subscription, payload.data() + 1, 4);
    if (subscription != 1) return;  // count each pair once, by its left eye
    std::memcpy(&stamp_ns, payload.data() + 5, 8);
    capture_ms = static_cast<double>(stamp_ns) / 1e6;
  }
  {
    std::lock_guard lock(mutex_);
    latencies_ms_.push_back(now_ms() - capture_ms);
  }
  ++images_;
}

void WsClient::run() {
  std::vector<uint8_t> payload;
  while (!stop_) {
    uint8_t h[2];
    if (!read_exact(fd_, h, 2, stop_)) return;
    uint64_t len = h[1] & 0x7f;
    if (len == 126 || len == 127) {
      uint8_t ext[8];
      const size_t n = len == 126 ? 2 : 8;
      if (!read_exact(fd_, ext, n, stop_)) return;
      len = 0;
      for (size_t i = 0; i < n; ++i) len = (len << 8) | ext[i];
    }
    payload.resize(len);
    if (len > 0 && !read_exact(fd_, payload.data(), len, stop_)) return;
    if ((h[0] & 0x0f) == 0x2) on_binary(payload);
  }
}

}  // namespace stereoball::bench
