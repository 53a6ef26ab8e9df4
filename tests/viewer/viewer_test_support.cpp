#include "viewer_test_support.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <random>
#include <regex>

#include "common/dds/participant.hpp"
#include "common/dds/writer.hpp"
#include "common/node/node_runner.hpp"
#include "stereoball/topics.hpp"

namespace stereoball::testing {

using namespace std::chrono_literals;

RunningViewer start_viewer(const std::string& partition, const std::vector<std::string>& extra) {
  std::vector<std::string> argv = {bin("stereoball-view"), "--port", "0", "--partition", partition};
  argv.insert(argv.end(), extra.begin(), extra.end());
  RunningViewer v{Process::start(argv), 0};
  if (!v.process.wait_for_output("viewer: http://127.0.0.1:", 30s)) return v;
  std::smatch m;
  const std::string out = v.process.output();
  if (std::regex_search(out, m, std::regex("viewer: http://127\\.0\\.0\\.1:(\\d+)/")))
    v.port = std::stoi(m[1]);
  return v;
}

KnownScene::KnownScene(const std::string& partition, double rate_hz, bool noise_frames) {
  thread_ = std::thread([this, partition, rate_hz, noise_frames] {
    dds::DomainParticipant p({test_domain(), partition});
    dds::DataWriter<stereoball_msg_StereoFrame> frames(p, topics::kStereoFrame);
    dds::DataWriter<stereoball_msg_BallDetection> detections(p, topics::kBallDetection);
    dds::DataWriter<stereoball_msg_BallTrack> tracks(p, topics::kBallTrack);
    dds::DataWriter<stereoball_msg_GroundTruth> truth(p, topics::kGroundTruth);
    const SceneValues& v = values_;
    std::vector<uint8_t> left(v.width_px * v.height_px * 3), right(left.size());
    std::mt19937 rng(7);
    for (size_t i = 0; i < left.size(); ++i) {
      // Noise does not compress: big JPEGs that fill a client's buffers quickly.
      left[i] = noise_frames ? static_cast<uint8_t>(rng()) : static_cast<uint8_t>(i / 3 % 251);
      right[i] = noise_frames ? static_cast<uint8_t>(rng()) : static_cast<uint8_t>(i / 7 % 253);
    }
    char source[] = "test", encoding[] = "bgr8", reason[] = "ok", scenario[] = "test";
    for (uint64_t seq = 0; !stop_; ++seq) {
      stereoball_msg_StereoFrame f{};
      f.seq = seq;
      f.stamp_ns = v.capture_stamp_ns;
      f.source = source;
      f.encoding = encoding;
      for (auto [eye, bytes] : {std::pair{&f.left, &left}, std::pair{&f.right, &right}}) {
        eye->capture_stamp_ns = v.capture_stamp_ns;
        eye->width_px = v.width_px;
        eye->height_px = v.height_px;
        eye->step_bytes = v.width_px * 3;
        eye->data._buffer = bytes->data();
        eye->data._length = static_cast<uint32_t>(bytes->size());
      }
      frames.write(f);
      ++frames_published_;
      stereoball_msg_BallDetection d{};
      d.frame_seq = seq;
      d.capture_stamp_ns = v.capture_stamp_ns;
      d.status = stereoball_msg_DETECTION_FOUND;
      d.reason = reason;
      d.left = {v.left_x, v.left_y, v.left_r, 0.9f};
      d.right = {v.right_x, v.left_y, v.right_r, 0.8f};
      detections.write(d);
      stereoball_msg_BallTrack t{};
      t.frame_seq = seq;
      t.capture_stamp_ns = v.capture_stamp_ns;
      t.state = stereoball_msg_TRACK_FOLLOWING;
      t.verdict = stereoball_msg_VERDICT_BLOCK_MATCH_ACCEPTED;
      t.reason = reason;
      t.position_valid = true;
      std::memcpy(t.position_m, v.track_position, sizeof t.position_m);
      t.distance_m = v.distance_m;
      tracks.write(t);
      stereoball_msg_GroundTruth g{};
      g.frame_seq = seq;
      g.stamp_ns = v.capture_stamp_ns;
      g.scenario = scenario;
      g.ball_present = true;
      g.ball_radius_m = 0.1;
      std::memcpy(g.ball_world_m, v.truth_ball_world, sizeof g.ball_world_m);
      g.robot_x_m = v.robot_xy[0];
      g.robot_y_m = v.robot_xy[1];
      truth.write(g);
      std::this_thread::sleep_for(std::chrono::nanoseconds(static_cast<int64_t>(1e9 / rate_hz)));
    }
  });
}

KnownScene::~KnownScene() {
  stop_ = true;
  thread_.join();
}

int tcp_connect(int port, int timeout_s) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return -1;
  timeval tv{timeout_s, 0};
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
  const int fd = tcp_connect(port, 5);
  if (fd < 0) return "";
  std::string response;
  const std::string request = "GET " + path + " HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n";
  if (send(fd, request.data(), request.size(), MSG_NOSIGNAL) > 0) {
    char buf[4096];
    // The server keeps the connection open: stop at the end of the body (Content-Length).
    for (ssize_t n; !http_response_complete(response) && (n = recv(fd, buf, sizeof buf, 0)) > 0;)
      response.append(buf, n);
  }
  close(fd);
  const auto body = response.find("\r\n\r\n");
  return body == std::string::npos ? "" : response.substr(body + 4);
}

long stat(int port, const std::string& name) {
  std::smatch m;
  const std::string body = http_get(port, "/stats");
  if (!std::regex_search(body, m, std::regex("\"" + name + "\":(\\d+)"))) return -1;
  return std::stol(m[1]);
}

void send_all(int fd, const std::string& bytes) {
  ::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL);
}

int ws_connect(int port, const std::string& subprotocol) {
  const int fd = tcp_connect(port, 10);
  if (fd < 0) return -1;
  send_all(fd,
           "GET / HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
           "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n" +
               (subprotocol.empty() ? "" : "Sec-WebSocket-Protocol: " + subprotocol + "\r\n") +
               "\r\n");
  std::string head;
  char c;
  while (head.find("\r\n\r\n") == std::string::npos && recv(fd, &c, 1, 0) == 1) head += c;
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

namespace {

// Reads n bytes, retrying on the socket's receive timeout until stop; false when closed.
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

}  // namespace

PageReader::PageReader(int port, bool acks) : ack_(acks) {
  fd_ = ws_connect(port);
  if (fd_ < 0) return;
  timeval tv{0, 200'000};
  setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  thread_ = std::thread([this] {
    std::vector<uint8_t> payload;
    for (uint8_t h[2]; !stop_ && read_exact(fd_, h, 2, stop_);) {
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
      if ((h[0] & 0x0f) != 0x2) continue;  // scenes are text
      ++pairs_;
      if (ack_) ack();
    }
  });
}

PageReader::~PageReader() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  if (fd_ >= 0) close(fd_);
}

void PageReader::ack() {
  send_all(fd_, client_frame(0x1, "ack"));
}

std::string npm_dir() {
  const char* dir = std::getenv("SB_VIEWER_NPM_DIR");
  if (!dir || !std::filesystem::exists(std::string(dir) + "/node_modules/ws")) return "";
  return dir;
}

std::string node_binary() {
  for (const char* p : {"/usr/bin/node", "/usr/local/bin/node"})
    if (std::filesystem::exists(p)) return p;
  return "";
}

}  // namespace stereoball::testing
