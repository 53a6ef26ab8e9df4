#include "viewer_test_support.hpp"

#include <chrono>
#include <cstring>
#include <filesystem>
#include <random>
#include <regex>

#include "common/dds/participant.hpp"
#include "common/dds/writer.hpp"
#include "common/node/node_runner.hpp"
#include "stereo/frame/preview_publisher.hpp"
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

KnownScene::KnownScene(const std::string& partition, double rate_hz, bool noise_frames,
                       bool with_preview) {
  thread_ = std::thread([this, partition, rate_hz, noise_frames, with_preview] {
    dds::DomainParticipant p({test_domain(), partition});
    dds::DataWriter<stereoball_msg_StereoFrame> frames(p, topics::kStereoFrame);
    std::unique_ptr<stereo::PreviewPublisher> preview;
    if (with_preview)
      preview = std::make_unique<stereo::PreviewPublisher>(p, stereo::FrameCodecParams{}, "test");
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
      frame_readers_ = frames.matched_readers();
      if (preview) {
        stereo::FrameView view;
        view.seq = seq;
        view.stamp_ns = v.capture_stamp_ns;
        view.encoding = "bgr8";
        view.left = {v.capture_stamp_ns, v.width_px,  v.height_px,
                     v.width_px * 3,     left.data(), left.size()};
        view.right = {v.capture_stamp_ns, v.width_px,   v.height_px,
                      v.width_px * 3,     right.data(), right.size()};
        preview->offer(view);
        previews_published_ = preview->published();
        preview_readers_ = preview->matched_readers();
      }
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

std::string chromium_binary() {
  for (const char* p : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (std::filesystem::exists(p)) return p;
  return "";
}

std::string test_out_dir(const std::string& name) {
  const char* root = std::getenv("SB_VIEWER_OUT_DIR");
  const std::filesystem::path dir = std::filesystem::path(root ? root : temp_dir()) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

}  // namespace stereoball::testing
