#include "ws_client.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstring>

namespace stereoball::bench {
namespace {

bool read_exact(int fd, void* out, size_t n) {
  auto* p = static_cast<uint8_t*>(out);
  while (n > 0) {
    const ssize_t r = recv(fd, p, n, 0);
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

}  // namespace

PageClient::PageClient(int port) {
  fd_ = socket(AF_INET, SOCK_STREAM, 0);
  timeval tv{1, 0};
  setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const std::string hello =
      "GET / HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
      "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n";
  std::string head;
  char c;
  if (connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0 &&
      send(fd_, hello.data(), hello.size(), MSG_NOSIGNAL) > 0) {
    while (head.find("\r\n\r\n") == std::string::npos && recv(fd_, &c, 1, 0) == 1) head += c;
  }
  if (head.rfind("HTTP/1.1 101", 0) != 0) {
    close(fd_);
    fd_ = -1;
    return;
  }
  thread_ = std::thread([this] { run(); });
}

PageClient::~PageClient() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  if (fd_ >= 0) close(fd_);
}

std::vector<double> PageClient::latencies_ms() const {
  std::lock_guard lock(mutex_);
  return latencies_ms_;
}

void PageClient::run() {
  // "ack", masked with a zero key (a client must mask; any key is valid).
  const uint8_t ack[] = {0x81, 0x83, 0, 0, 0, 0, 'a', 'c', 'k'};
  std::vector<uint8_t> payload;
  while (!stop_) {
    uint8_t h[2];
    if (!read_exact(fd_, h, 2)) {
      if (errno == EAGAIN || errno == EWOULDBLOCK) continue;
      return;
    }
    uint64_t len = h[1] & 0x7f;
    if (len == 126 || len == 127) {
      uint8_t ext[8];
      const size_t n = len == 126 ? 2 : 8;
      if (!read_exact(fd_, ext, n)) return;
      len = 0;
      for (size_t i = 0; i < n; ++i) len = (len << 8) | ext[i];
    }
    payload.resize(len);
    if (len > 0 && !read_exact(fd_, payload.data(), len)) return;
    const uint8_t opcode = h[0] & 0x0f;
    uint32_t type = 0;
    if (opcode == 0x2 && len >= 24) std::memcpy(&type, payload.data(), 4);
    if (type != 1) continue;
    double capture_ms;
    std::memcpy(&capture_ms, payload.data() + 16, 8);
    {
      std::lock_guard lock(mutex_);
      latencies_ms_.push_back(now_ms() - capture_ms);
    }
    ++images_;
    send(fd_, ack, sizeof ack, MSG_NOSIGNAL);
  }
}

}  // namespace stereoball::bench
