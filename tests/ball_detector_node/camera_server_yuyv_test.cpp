// Integration test (issue 38, real rig): camera_server streaming two YUYV cameras (scripted
// ones) with publish_encoding: native puts yuyv frames on stereo/frame, and the real
// ball_detector process finds the ball in them.

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "camera_server/io/fake_video_device.hpp"
#include "camera_server/node/camera_server_node.hpp"
#include "common/dds/reader.hpp"
#include "process.hpp"
#include "simulator/core/ball_scene.hpp"
#include "stereo/io/calibration_file.hpp"
#include "yuyv_images.hpp"

namespace {

namespace cs = stereoball::camera_server;
using namespace std::chrono_literals;

constexpr int64_t kYuyvPeriodNs = 33'333'333;

// A rendered one-colour ball 1.5 m ahead in a plain room, its calibration, and both eyes
// packed as a YUYV camera delivers them.
struct YuyvScene {
  stereoball::simulator::SimFrame frame;
  stereoball::stereo::StereoCalibration calib;
  std::vector<uint8_t> left_yuyv, right_yuyv;
};

YuyvScene render_yuyv_scene() {
  stereoball::simulator::SimBallSetup setup;
  setup.ball_x_m = 1.5;
  setup.ball_y_m = 0.0;
  setup.clutter = false;
  setup.plain_room = true;
  setup.uniform_ball = true;
  stereoball::simulator::Simulator sim(stereoball::simulator::default_sim_params(),
                                       stereoball::simulator::make_sim_scenario(setup));
  YuyvScene s{sim.step(std::nullopt, 0), sim.calibration(), {}, {}};
  s.left_yuyv = stereoball::testing::yuyv_from_bgr(s.frame.left);
  s.right_yuyv = stereoball::testing::yuyv_from_bgr(s.frame.right);
  return s;
}

// A camera offering YUYV at the scene's size, 30 Hz.
std::shared_ptr<cs::FakeCamera> yuyv_camera(cv::Size size) {
  auto cam = std::make_shared<cs::FakeCamera>();
  cs::SizeOffer offer;
  offer.min_width_px = offer.max_width_px = static_cast<uint32_t>(size.width);
  offer.min_height_px = offer.max_height_px = static_cast<uint32_t>(size.height);
  offer.rates_hz = {30.0};
  cam->formats = {{cs::kFourccYuyv, "YUYV 4:2:2", {offer}}};
  return cam;
}

}  // namespace

// Given two YUYV cameras seeing the ball, camera_server publishing their bytes as captured
// (publish_encoding: native) with the rig's calibration, and the ball_detector process,
// when the cameras stream, then the frames on stereo/frame are yuyv and the detector answers
// them with the ball where it was rendered (within a pixel or two: YUYV halves the chroma).
TEST(CameraServerYuyvToBallDetector, GivenNativeYuyvCameras_ThenTheDetectorFindsTheBall) {
  const YuyvScene scene = render_yuyv_scene();
  const cv::Size size = scene.frame.left.size();
  const std::string calibration = stereoball::testing::temp_dir() + "/yuyv_rig.yaml";
  ASSERT_TRUE(stereoball::stereo::save_calibration(calibration, scene.calib).ok());

  const std::string partition = stereoball::testing::unique_partition();
  auto detector = stereoball::testing::Process::start(
      {stereoball::testing::bin("ball_detector"), "--config",
       stereoball::testing::source_path("config/ball_detector.yaml"), "--domain",
       std::to_string(stereoball::testing::test_domain()), "--partition", partition});
  stereoball::node::CommonOptions options;
  options.domain_id = stereoball::testing::test_domain();
  options.partition = partition;
  stereoball::node::Runner runner("camera_server", options);
  stereoball::dds::DataReader<stereoball_msg_StereoFrame> frames(runner.participant(),
                                                                 stereoball::topics::kStereoFrame);
  stereoball::dds::DataReader<stereoball_msg_BallDetection> detections(
      runner.participant(), stereoball::topics::kBallDetection);

  cs::CameraServerParams params;
  params.left_device = "/fake/left";
  params.right_device = "/fake/right";
  params.width_px = static_cast<uint32_t>(size.width);
  params.height_px = static_cast<uint32_t>(size.height);
  params.pixel_format = "yuyv";
  params.publish_encoding = "native";
  params.calibration_file = calibration;
  auto left = yuyv_camera(size);
  auto right = yuyv_camera(size);
  auto node = cs::CameraServerNode::create(
      params, runner, [left, right](cs::Eye e) -> std::unique_ptr<cs::VideoDevice> {
        return std::make_unique<cs::FakeVideoDevice>(e == cs::Eye::kLeft ? left : right);
      });
  ASSERT_TRUE(node) << node.error();
  std::thread loop([&] { runner.run(); });

  // When the cameras stream (a pair queued whenever the last was taken, stamps 30 Hz apart)
  int64_t stamp_ns = 100'000'000'000;
  std::vector<std::string> encodings;
  std::optional<stereoball_msg_BallDetection> found;
  std::string last_reason;
  const bool done = stereoball::testing::eventually(
      [&] {
        if (left->queued() == 0 && right->queued() == 0) {
          stamp_ns += kYuyvPeriodNs;
          left->push({stamp_ns, scene.left_yuyv, 0});
          right->push({stamp_ns + 1'000'000, scene.right_yuyv, 0});
        }
        for (auto& f : frames.take()) encodings.emplace_back(f->encoding ? f->encoding : "");
        for (auto& d : detections.take()) {
          last_reason = d->reason ? d->reason : "";
          if (d->status == stereoball_msg_DETECTION_FOUND) found = *d;
        }
        return found.has_value();
      },
      30s);
  runner.stop();
  loop.join();
  node->reset();

  // Then
  ASSERT_TRUE(done) << "no ball found; last reason '" << last_reason << "'\n" << detector.output();
  ASSERT_FALSE(encodings.empty());
  for (const auto& e : encodings) EXPECT_EQ(e, "yuyv");
  const auto& t = scene.frame.truth;
  EXPECT_NEAR(found->left.x_px, t.ball_left_px.x, 1.5);
  EXPECT_NEAR(found->left.y_px, t.ball_left_px.y, 1.5);
  EXPECT_NEAR(found->right.x_px, t.ball_right_px.x, 2.5);
  EXPECT_NEAR(found->right.y_px, t.ball_right_px.y, 2.5);
  const double dist_m = std::hypot(t.ball_camera_m.x, t.ball_camera_m.y, t.ball_camera_m.z);
  const double err_m =
      std::hypot(found->position_m[0] - t.ball_camera_m.x, found->position_m[1] - t.ball_camera_m.y,
                 found->position_m[2] - t.ball_camera_m.z);
  EXPECT_LT(err_m, 0.03 * dist_m);
  // The ball is orange: R > B at the patch centre (U and V taken the right way round).
  ASSERT_TRUE(found->patch_valid);
  const int centre = (10 * 21 + 10) * 3;
  EXPECT_GT(found->patch_rgb[centre], found->patch_rgb[centre + 2] + 40);
  std::printf(
      "[figure] yuyv via camera_server: left (%.2f, %.2f) px vs truth (%.2f, %.2f), "
      "position error %.4f m at %.3f m\n",
      found->left.x_px, found->left.y_px, t.ball_left_px.x, t.ball_left_px.y, err_m, dist_m);
}
