#include "view_client.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <regex>
#include <span>

namespace stereoball::view_client {
namespace {

// Foxglove channels 1 and 2 are the left and right eye (view/left/image, view/right/image).
constexpr char kSubscribeEyes[] =
    R"({"op":"subscribe","subscriptions":[{"id":1,"channelId":1},{"id":2,"channelId":2}]})";

double now_ms() {
  return std::chrono::duration<double, std::milli>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

int tcp_connect(int port, int recv_timeout_ms) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return -1;
  timeval tv{recv_timeout_ms / 1000, (recv_timeout_ms % 1000) * 1000};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    close(fd);
    return -1;
  }
  return fd;
}

void send_all(int fd, const std::string& bytes) {
  for (size_t at = 0; at < bytes.size();) {
    const ssize_t n = ::send(fd, bytes.data() + at, bytes.size() - at, MSG_NOSIGNAL);
    if (n <= 0) return;
    at += static_cast<size_t>(n);
  }
}

bool http_response_complete(const std::string& response) {
  const auto head_end = response.find("\r\n\r\n");
  if (head_end == std::string::npos) return false;
  std::smatch m;
  const std::string head = response.substr(0, head_end);
  if (!std::regex_search(head, m, std::regex("Content-Length: *(\\d+)", std::regex::icase)))
    return false;
  return response.size() - head_end - 4 >= std::stoul(m[1]);
}

std::string http_get(int port, const std::string& path) {
  const int fd = tcp_connect(port, 200);
  if (fd < 0) return "";
  std::string response;
  send_all(fd, "GET " + path + " HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  char buf[4096];
  // The server keeps the connection open: stop at the end of the body (Content-Length).
  for (int timeouts = 0; timeouts < 25 && !http_response_complete(response);) {
    const ssize_t n = recv(fd, buf, sizeof buf, 0);
    if (n > 0) {
      response.append(buf, static_cast<size_t>(n));
    } else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      ++timeouts;
    } else {
      break;
    }
  }
  close(fd);
  const auto body = response.find("\r\n\r\n");
  return body == std::string::npos ? "" : response.substr(body + 4);
}

long stats_counter(int port, const std::string& name) {
  std::smatch m;
  const std::string body = http_get(port, "/stats");
  if (!std::regex_search(body, m, std::regex("\"" + name + "\":(\\d+)"))) return -1;
  return std::stol(m[1]);
}

int ws_connect(int port, const std::string& subprotocol, int recv_timeout_ms) {
  const int fd = tcp_connect(port, recv_timeout_ms);
  if (fd < 0) return -1;
  send_all(fd,
           "GET / HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
           "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n" +
               (subprotocol.empty() ? "" : "Sec-WebSocket-Protocol: " + subprotocol + "\r\n") +
               "\r\n");
  std::string head;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  for (char c; head.find("\r\n\r\n") == std::string::npos;) {
    const ssize_t n = recv(fd, &c, 1, 0);
    if (n == 1) {
      head += c;
    } else if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK) ||
               std::chrono::steady_clock::now() > end) {
      break;
    }
  }
  if (head.rfind("HTTP/1.1 101", 0) != 0) {
    close(fd);
    return -1;
  }
  return fd;
}

std::string client_frame(uint8_t opcode, const std::string& payload, bool masked) {
  std::string f(1, static_cast<char>(0x80 | opcode));
  const uint8_t mask_bit = masked ? 0x80 : 0;
  if (payload.size() < 126) {
    f += static_cast<char>(mask_bit | payload.size());
  } else {
    f += static_cast<char>(mask_bit | 127);
    for (int i = 7; i >= 0; --i)
      f += static_cast<char>((uint64_t{payload.size()} >> (8 * i)) & 0xff);
  }
  if (masked) f += std::string(4, '\0');
  return f + payload;
}

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

bool read_message(int fd, uint8_t& opcode, std::vector<uint8_t>& payload,
                  const std::atomic<bool>& stop) {
  uint8_t h[2];
  if (!read_exact(fd, h, 2, stop)) return false;
  uint64_t len = h[1] & 0x7f;
  if (len == 126 || len == 127) {
    uint8_t ext[8];
    const size_t n = len == 126 ? 2 : 8;
    if (!read_exact(fd, ext, n, stop)) return false;
    len = 0;
    for (size_t i = 0; i < n; ++i) len = (len << 8) | ext[i];
  }
  if (len > (64u << 20)) return false;  // the viewer never sends that much at once
  opcode = h[0] & 0x0f;
  payload.resize(len);
  return len == 0 || read_exact(fd, payload.data(), len, stop);
}

WsClient::WsClient(int port, Kind kind, bool acks) : kind_(kind), acks_(acks) {
  // A short receive timeout lets the reader notice that it should stop while nothing comes.
  fd_ = ws_connect(port, kind == Kind::kFoxglove ? "foxglove.websocket.v1" : "", 200);
  if (fd_ < 0) return;
  if (kind_ == Kind::kFoxglove) send_all(fd_, client_frame(0x1, kSubscribeEyes));
  thread_ = std::thread([this] { run(); });
}

WsClient::~WsClient() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  if (fd_ < 0) return;
  if (clean_close_) send_all(fd_, client_frame(0x8, std::string("\x03\xe8", 2)));  // 1000
  close(fd_);
}

std::vector<PairTiming> WsClient::timings() const {
  std::lock_guard lock(mutex_);
  return timings_;
}

std::optional<viewer::PairHeader> WsClient::last_pair() const {
  std::lock_guard lock(mutex_);
  return last_pair_;
}

std::vector<double> WsClient::latencies_ms() const {
  std::vector<double> out;
  for (const auto& t : timings()) out.push_back(t.capture_to_received);
  return out;
}

void WsClient::ack() {
  send_all(fd_, client_frame(0x1, "ack"));
}

void WsClient::on_binary(const std::vector<uint8_t>& payload) {
  const double received = now_ms();
  PairTiming t;
  if (kind_ == Kind::kPage) {
    const auto h = viewer::parse_pair_header(payload);
    if (!h) {
      // A viewer built before the 48-byte header (a benchmark's baseline) sent type 1: the
      // left length, seq and capture ms in 24 bytes; only the whole way is known.
      uint32_t type = 0;
      double capture_ms = 0;
      if (payload.size() < 24) return;
      std::memcpy(&type, payload.data(), 4);
      std::memcpy(&capture_ms, payload.data() + 16, 8);
      if (type != 1) return;
      if (acks_) ack();
      t.capture_to_received = received - capture_ms;
      std::lock_guard lock(mutex_);
      timings_.push_back(t);
      ++images_;
      return;
    }
    if (acks_) ack();
    t.capture_to_taken = h->received_ms - h->capture_ms;
    t.taken_to_encoded = h->encoded_ms - h->received_ms;
    t.encoded_to_received = received - h->encoded_ms;
    t.capture_to_received = received - h->capture_ms;
    std::lock_guard lock(mutex_);
    last_pair_ = h;
  } else {
    // Message Data: opcode 1, subscription id u32, log time u64 ns (the capture time), data
    uint32_t subscription = 0;
    uint64_t stamp_ns = 0;
    if (payload.size() < 13 || payload[0] != 1) return;
    std::memcpy(&subscription, payload.data() + 1, 4);
    if (subscription != 1) return;  // count each pair once, by its left eye
    std::memcpy(&stamp_ns, payload.data() + 5, 8);
    t.capture_to_received = received - static_cast<double>(stamp_ns) / 1e6;
  }
  {
    std::lock_guard lock(mutex_);
    timings_.push_back(t);
  }
  ++images_;
}

void WsClient::run() {
  std::vector<uint8_t> payload;
  for (uint8_t opcode = 0; !stop_ && read_message(fd_, opcode, payload, stop_);)
    if (opcode == 0x2) on_binary(payload);  // scenes and statuses are text
}

}  // namespace stereoball::view_client
