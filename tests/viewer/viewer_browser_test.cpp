// A real browser (headless Chromium) on the viewer page: during a short demo scenario the
// page's own state shows images, detection overlays and track states arriving and updating;
// and the page reconnects by itself when the viewer restarts. Screenshots and the page state
// go to the test's output folder (SB_VIEWER_OUT_DIR).

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>

#include "viewer_test_support.hpp"

namespace stereoball::testing {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

// A port nobody listens on right now (bound once with port 0, then released).
int free_port() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
  socklen_t len = sizeof addr;
  getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  close(fd);
  return ntohs(addr.sin_port);
}

class ViewerBrowser : public ::testing::Test {
 protected:
  void SetUp() override {
    if (chromium_binary().empty())
      GTEST_SKIP() << "Chromium is not installed (Debian package `chromium`; run.sh installs it)";
    if (node_binary().empty() || npm_dir().empty())
      GTEST_SKIP() << "node or the tests' npm packages are missing (SB_VIEWER_NPM_DIR)";
  }
};

TEST_F(ViewerBrowser, PageShowsImagesOverlaysAndTrackDuringTheDemo) {
  // Given the demo with --view on a free port
  const int port = free_port();
  const std::string out = test_out_dir("demo");
  auto demo = Process::start({bin("stereoball-demo"), "--scenario", "ball_rolling_away",
                              "--duration", "40", "--view", "--view-port", std::to_string(port),
                              "--domain", std::to_string(test_domain()), "--out", out + "/report"});
  const std::string url = "http://127.0.0.1:" + std::to_string(port) + "/";
  ASSERT_TRUE(demo.wait_for_output("viewer: " + url, 60s)) << demo.output();
  // When Chromium loads the page
  const auto [rc, log] =
      run({node_binary(), npm_dir() + "/browser_check.mjs", url, out, chromium_binary()}, 240s);
  // Then the page's own counters show images, overlays and track updates arriving and updating
  EXPECT_EQ(rc, 0) << log << "\n--- demo:\n" << demo.output();
  EXPECT_TRUE(fs::exists(out + "/viewer.png")) << log;
  std::printf("%s", log.c_str());
  demo.signal(SIGINT);
  EXPECT_TRUE(demo.wait_for_exit(60s).has_value());
}

TEST_F(ViewerBrowser, PageReconnectsWhenTheViewerRestarts) {
  // Given a viewer on a fixed port, a published scene and the page live in Chromium
  const std::string partition = unique_partition();
  const std::string port = std::to_string(free_port());
  const std::vector<std::string> argv = {bin("stereoball-view"), "--port", port, "--partition",
                                         partition};
  KnownScene scene(partition, 20);
  auto viewer = Process::start(argv);
  ASSERT_TRUE(viewer.wait_for_output("viewer: http://", 30s)) << viewer.output();
  const std::string out = test_out_dir("reconnect");
  auto browser =
      Process::start({node_binary(), npm_dir() + "/browser_check.mjs",
                      "http://127.0.0.1:" + port + "/", out, chromium_binary(), "--reconnect"});
  ASSERT_TRUE(eventually([&] { return fs::exists(out + "/phase1") || !browser.running(); }, 150s))
      << browser.output();
  ASSERT_TRUE(fs::exists(out + "/phase1")) << browser.output();
  // When the viewer stops and starts again on the same port
  viewer.signal(SIGTERM);
  ASSERT_TRUE(viewer.wait_for_exit(30s).has_value());
  // (once the page has seen it go away, so the restart is not missed between two looks)
  ASSERT_TRUE(eventually([&] { return fs::exists(out + "/down") || !browser.running(); }, 60s))
      << browser.output();
  auto restarted = Process::start(argv);
  ASSERT_TRUE(restarted.wait_for_output("viewer: http://", 30s)) << restarted.output();
  // Then the page reconnects by itself and images flow again
  const auto rc = browser.wait_for_exit(150s);
  ASSERT_TRUE(rc.has_value()) << browser.output();
  EXPECT_EQ(*rc, 0) << browser.output();
}

TEST_F(ViewerBrowser, OverlayIsScaledWithAnEyeShownSmallerThanItIs) {
  // Given 320x240 eyes with a known left circle, and a viewer that shows them 160 px wide
  const std::string partition = unique_partition();
  KnownScene scene(partition, 20);
  auto viewer = start_viewer(partition, {"--max-width", "160"});
  ASSERT_GT(viewer.port, 0) << viewer.process.output();
  const std::string out = test_out_dir("scaled");
  // When Chromium shows the page
  const SceneValues& v = scene.values();
  char expected[96];
  std::snprintf(expected, sizeof expected, "--overlay=%g,%g,%g", v.left_x / 2, v.left_y / 2,
                v.left_r / 2);
  const auto [rc, log] = run(
      {node_binary(), npm_dir() + "/browser_check.mjs",
       "http://127.0.0.1:" + std::to_string(viewer.port) + "/", out, chromium_binary(), expected},
      240s);
  // Then the circle is drawn at half the detector's coordinates and radius, on the eye
  EXPECT_EQ(rc, 0) << log;
  std::printf("%s", log.c_str());
}

}  // namespace
}  // namespace stereoball::testing
