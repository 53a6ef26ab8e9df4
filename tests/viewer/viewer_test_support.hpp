#pragma once
// Shared by the viewer's integration tests: start `stereoball view` on this test's domain and
// partition, publish a known scene, find the npm clients (HTTP and WebSocket clients:
// tools/view/client).

#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include "process.hpp"
#include "view_client.hpp"

namespace stereoball::testing {

/// A running viewer and the port it bound.
struct RunningViewer {
  Process process;
  int port = 0;
};

/// Starts stereoball-view on port 0 (any free port) with extra args; port 0 in the result
/// when it did not report its address in time.
RunningViewer start_viewer(const std::string& partition,
                           const std::vector<std::string>& extra = {});

/// What KnownScene publishes, for the assertions.
struct SceneValues {
  uint32_t width_px = 320, height_px = 240;
  int64_t capture_stamp_ns = 1'700'000'000'123'456'789;
  float left_x = 100.5f, left_y = 80.25f, left_r = 12.0f;
  float right_x = 90.5f, right_r = 11.5f;
  double track_position[3] = {0.25, 0.1, 1.5};
  double distance_m = 1.52;
  double truth_ball_world[3] = {2.0, -0.5, 0.1};
  double robot_xy[2] = {0.5, -0.25};
};

/// Publishes frames (noise or smooth), detections, tracks and ground truth at rate_hz on its
/// own thread until destroyed; with_preview: also stereo/preview beside the frames, as
/// camera_server and the simulator do (stereo/frame/preview_publisher.hpp).
class KnownScene {
 public:
  KnownScene(const std::string& partition, double rate_hz, bool noise_frames = false,
             bool with_preview = false);
  ~KnownScene();
  const SceneValues& values() const { return values_; }
  /// Stereo frames written so far.
  uint64_t frames_published() const { return frames_published_.load(); }
  /// Previews made and published so far (0 without with_preview).
  uint64_t previews_published() const { return previews_published_.load(); }
  /// Readers matched now with the stereo/frame writer, and with the stereo/preview writer.
  uint32_t frame_readers() const { return frame_readers_.load(); }
  uint32_t preview_readers() const { return preview_readers_.load(); }

 private:
  SceneValues values_;
  std::atomic<bool> stop_{false};
  std::atomic<uint64_t> frames_published_{0};
  std::atomic<uint64_t> previews_published_{0};
  std::atomic<uint32_t> frame_readers_{0}, preview_readers_{0};
  std::thread thread_;
};

// HTTP, WebSocket and page-like clients, shared with the viewer's benchmark.
using view_client::client_frame;
using view_client::http_get;
using view_client::send_all;
using view_client::stats_counter;
using view_client::tcp_connect;
using view_client::ws_connect;
using view_client::WsClient;

/// Folder with the tests' npm packages and scripts (SB_VIEWER_NPM_DIR), "" when unset or
/// not installed.
std::string npm_dir();
/// Path of node, "" when not installed.
std::string node_binary();
/// Path of Chromium, "" when not installed.
std::string chromium_binary();
/// A fresh empty folder `name` for a test's screenshots and page state (under
/// SB_VIEWER_OUT_DIR, else a temporary folder).
std::string test_out_dir(const std::string& name);

}  // namespace stereoball::testing
