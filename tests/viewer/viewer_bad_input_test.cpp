// Bad input at `stereoball view`'s boundary: a busy port or a bad address, malformed
// WebSocket frames and non-HTTP bytes, oversized messages, and a client that never reads.
// The viewer must name the problem, drop the offender and keep serving everyone else.

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <thread>

#include "viewer_test_support.hpp"

namespace stereoball::testing {
namespace {

using namespace std::chrono_literals;

// True when the server closed the connection within the socket timeout (data before the
// close is read and discarded).
bool closed_by_server(int fd) {
  char buf[65536];
  for (;;) {
    const ssize_t n = recv(fd, buf, sizeof buf, 0);
    if (n == 0 || (n < 0 && errno == ECONNRESET)) return true;
    if (n < 0) return false;  // timeout: still open
  }
}

TEST(ViewerBadInput, BusyPortAndBadAddressAreNamed) {
  // Given a port someone else listens on
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  ASSERT_EQ(listen(fd, 1), 0);
  socklen_t len = sizeof addr;
  getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  const std::string port = std::to_string(ntohs(addr.sin_port));
  // When the viewer is asked to use it, it exits with one clear line
  auto [rc, out] =
      run({bin("stereoball-view"), "--port", port, "--partition", unique_partition()}, 30s);
  EXPECT_EQ(rc, 1) << out;
  EXPECT_NE(out.find("cannot listen on 127.0.0.1:" + port + ": Address already in use"),
            std::string::npos)
      << out;
  close(fd);
  // And an address that is not one is named too
  std::tie(rc, out) = run({bin("stereoball-view"), "--bind", "robot.local", "--port", "0"}, 30s);
  EXPECT_EQ(rc, 1) << out;
  EXPECT_NE(out.find("'robot.local' is not an IP address"), std::string::npos) << out;
}

TEST(ViewerBadInput, MalformedFramesAndBytesCloseOnlyThatConnection) {
  const std::string partition = unique_partition();
  auto viewer = start_viewer(partition);
  ASSERT_GT(viewer.port, 0) << viewer.process.output();
  struct Case {
    const char* what;
    std::string bytes;
    bool handshake;
  };
  const std::vector<Case> cases = {
      {"reserved opcode", client_frame(0x3, "x"), true},
      {"unmasked client frame", client_frame(0x1, "ack", false), true},
      {"invalid UTF-8 text", client_frame(0x1, "\xff\xfe\xfd"), true},
      {"message over 64 KB", client_frame(0x1, std::string(100'000, 'a')), true},
      {"TLS hello on the plain port",
       std::string("\x16\x03\x01\x02\x00\x01\x00\x01\xfc", 9) + std::string(200, '\x07') +
           "\r\n\r\n",
       false},
  };
  for (const auto& c : cases) {
    // Given a connection (WebSocket, or raw TCP for non-HTTP bytes)
    const int fd = c.handshake ? ws_connect(viewer.port) : tcp_connect(viewer.port, 10'000);
    ASSERT_GE(fd, 0) << c.what;
    // When it sends the bad bytes
    send_all(fd, c.bytes);
    // Then the server closes it, and still serves new clients
    EXPECT_TRUE(closed_by_server(fd)) << c.what;
    close(fd);
    EXPECT_GE(stats_counter(viewer.port, "connections"), 0) << "after " << c.what;
    const int again = ws_connect(viewer.port, "foxglove.websocket.v1");
    EXPECT_GE(again, 0) << "after " << c.what;
    if (again >= 0) close(again);
  }
  EXPECT_TRUE(viewer.process.running());
}

TEST(ViewerBadInput, ClientThatNeverReadsIsDroppedWhileOthersKeepReceiving) {
  // Given a viewer that cuts stalled clients after 1 s, and big (noise) frames at 30 Hz
  const std::string partition = unique_partition();
  auto viewer = start_viewer(partition, {"--client-stall-s", "1"});
  ASSERT_GT(viewer.port, 0) << viewer.process.output();
  KnownScene scene(partition, 30, /*noise_frames=*/true);
  const std::string subscribe = client_frame(
      0x1, R"({"op":"subscribe","subscriptions":[{"id":1,"channelId":1},{"id":2,"channelId":2}]})");
  // And a Foxglove client that reads everything
  const int reader = ws_connect(viewer.port, "foxglove.websocket.v1");
  ASSERT_GE(reader, 0);
  send_all(reader, subscribe);
  std::atomic<uint64_t> received{0};
  std::atomic<bool> stop{false};
  std::thread drain([&] {
    char buf[65536];
    while (!stop) {
      const ssize_t n = recv(reader, buf, sizeof buf, 0);
      if (n <= 0) break;
      received += static_cast<uint64_t>(n);
    }
  });
  // When another client subscribes to both eyes and never reads
  const int stuck = ws_connect(viewer.port, "foxglove.websocket.v1");
  ASSERT_GE(stuck, 0);
  int small = 4096;
  setsockopt(stuck, SOL_SOCKET, SO_RCVBUF, &small, sizeof small);
  send_all(stuck, subscribe);
  // Then the viewer cuts it off
  EXPECT_TRUE(eventually([&] { return stats_counter(viewer.port, "disconnected_slow") >= 1; }, 60s))
      << http_get(viewer.port, "/stats");
  // And the reading client still gets images afterwards
  const uint64_t before = received;
  EXPECT_TRUE(eventually([&] { return received > before + 100'000; }, 20s))
      << http_get(viewer.port, "/stats");
  EXPECT_EQ(stats_counter(viewer.port, "foxglove_clients"), 1);
  stop = true;
  shutdown(reader, SHUT_RDWR);
  drain.join();
  close(reader);
  close(stuck);
}

TEST(ViewerCalibrationPage, ServedOnlyInCalibrationModeAndWritesNothingBeforeAPassingVerdict) {
  // Given a viewer without --calibrate
  const std::string partition = unique_partition();
  auto plain = start_viewer(partition);
  ASSERT_GT(plain.port, 0) << plain.process.output();
  // Then /calibrate says how to start it, and the page's buttons are counted as bad messages
  EXPECT_NE(http_get(plain.port, "/calibrate").find("stereoball calibrate live"),
            std::string::npos);
  EXPECT_EQ(http_get(plain.port, "/calibrate/state"), "not found\n");
  const int page = ws_connect(plain.port);
  ASSERT_GE(page, 0);
  send_all(page, client_frame(0x1, "calibrate:write"));
  EXPECT_TRUE(
      eventually([&] { return stats_counter(plain.port, "bad_client_messages") >= 1; }, 10s));
  close(page);
  // Given --calibrate with a bad board or no output file
  const auto bad_board = run({bin("stereoball-view"), "--calibrate", "--board", "9y6", "-o",
                              temp_dir() + "/x.yaml", "--port", "0"},
                             20s);
  EXPECT_EQ(bad_board.first, 2);
  EXPECT_NE(bad_board.second.find("--board '9y6'"), std::string::npos) << bad_board.second;
  const auto no_output = run({bin("stereoball-view"), "--calibrate", "--port", "0"}, 20s);
  EXPECT_EQ(no_output.first, 2);
  EXPECT_NE(no_output.second.find("-o FILE"), std::string::npos) << no_output.second;
  // Given the calibration page with no frames at all
  const std::string file = temp_dir() + "/rig.yaml";
  auto cal = start_viewer(partition + ".none",
                          {"--calibrate", "-o", file, "--stall-s", "0.5", "--board", "9x6"});
  ASSERT_GT(cal.port, 0) << cal.process.output();
  // When its write button is pressed
  const int cal_page = ws_connect(cal.port);
  ASSERT_GE(cal_page, 0);
  send_all(cal_page, client_frame(0x1, "calibrate:write"));
  // Then nothing is written, and the state and the log say why
  EXPECT_TRUE(eventually(
      [&] {
        return http_get(cal.port, "/calibrate/state").find("no verdict yet") != std::string::npos;
      },
      10s))
      << http_get(cal.port, "/calibrate/state");
  EXPECT_TRUE(eventually(
      [&] {
        return http_get(cal.port, "/calibrate/state").find("no frames for") != std::string::npos;
      },
      10s));
  const std::string state = http_get(cal.port, "/calibrate/state");
  EXPECT_NE(state.find("\"phase\":\"waiting\""), std::string::npos) << state;
  EXPECT_NE(state.find("\"stalled\":true"), std::string::npos) << state;
  EXPECT_FALSE(std::filesystem::exists(file));
  EXPECT_TRUE(cal.process.wait_for_output("calibration: no verdict yet", 5s))
      << cal.process.output();
  close(cal_page);
}

}  // namespace
}  // namespace stereoball::testing
