// The camera_server node streaming from cameras (scripted ones): its capture thread pairs and
// publishes the frames while the runner's loop publishes health, and its preview worker
// encodes previews for a reader; swapped YUYV cameras are reported whatever the encoding. Run under
// ThreadSanitizer (tools/tsan_tests.sh) this is the capture thread's race check.

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "camera_server/io/fake_rig.hpp"
#include "camera_server/node/camera_server_node.hpp"
#include "common/dds/reader.hpp"
#include "process.hpp"
#include "yuyv_images.hpp"

namespace stereoball::camera_server {
namespace {

using namespace std::chrono_literals;
using namespace camera_server::testing;

constexpr int kPairs = 40;

TEST(CameraServerCapture, GivenTwoCamerasThenTheCaptureThreadPublishesEveryPairAndAPreview) {
  // Given two cameras with 40 frames each, stamped 3 ms apart between the eyes
  auto left = make_camera();
  auto right = make_camera();
  const int64_t start_ns = 100'000'000'000;
  for (int i = 0; i < kPairs; ++i) {
    left->push(yuyv_frame(start_ns + i * kPeriodNs, static_cast<uint8_t>(i)));
    right->push(yuyv_frame(start_ns + i * kPeriodNs + 3'000'000, static_cast<uint8_t>(100 + i)));
  }
  node::CommonOptions options;
  options.domain_id = stereoball::testing::test_domain();
  options.partition = stereoball::testing::unique_partition();
  node::Runner runner("camera_server", options);
  // (readers on the node's own participant match its writers as they are created)
  dds::DataReader<stereoball_msg_StereoFrame> frames(runner.participant(), topics::kStereoFrame);
  dds::DataReader<stereoball_msg_StereoPreview> previews(runner.participant(),
                                                         topics::kStereoPreview);
  // When the node streams them, its runner looping on another thread
  auto node = CameraServerNode::create(rig_params(), runner, factory(left, right));
  ASSERT_TRUE(node) << node.error();
  std::thread loop([&] { runner.run(); });
  // Then the pairs are published in order up to the last one (a frame reader keeps only the
  // newest: stale frames never queue), and a preview of one of them
  std::vector<uint64_t> seqs;
  uint64_t preview_seq = 0;
  bool preview_seen = false;
  const bool done = stereoball::testing::eventually(
      [&] {
        for (auto& f : frames.take(64)) seqs.push_back(f->seq);
        for (auto& p : previews.take()) {
          preview_seen = true;
          preview_seq = p->seq;
        }
        return !seqs.empty() && seqs.back() == kPairs - 1 && preview_seen;
      },
      20s);
  runner.stop();
  loop.join();
  node->reset();
  ASSERT_TRUE(done) << "newest pair " << (seqs.empty() ? -1 : static_cast<int64_t>(seqs.back()))
                    << ", preview " << (preview_seen ? "seen" : "not seen");
  EXPECT_TRUE(std::is_sorted(seqs.begin(), seqs.end()) &&
              std::adjacent_find(seqs.begin(), seqs.end()) == seqs.end());
  EXPECT_LT(preview_seq, static_cast<uint64_t>(kPairs));
}

// An OpenCV sample image (640x480, the rig of config/calibration/opencv_samples_stereo.yaml) as
// a camera delivers it: YUYV bytes, or for MJPEG the JPEG file itself.
std::vector<uint8_t> sample_frame(const std::string& name, uint32_t fourcc) {
  const std::string path = std::string(SB_SHARED_DATA_DIR) + "/opencv-samples/" + name;
  if (fourcc == kFourccMjpeg) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  const cv::Mat grey = cv::imread(path, cv::IMREAD_GRAYSCALE);
  if (grey.empty()) return {};
  cv::Mat bgr;
  cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
  return stereoball::testing::yuyv_from_bgr(bgr);
}

// What camera_server said about the eye order of a stream.
struct EyeOrderReport {
  uint64_t eyes_swapped = 0;  // health errors "eyes_swapped"
  uint64_t eye_order = 0;     // health errors "eye_order" (an eye that could not be checked)
  std::string last_error;
  std::string encoding;  // of the frames on stereo/frame
  bool published = false;
};

// camera_server on two 640x480 cameras of the given format delivering left_frame and
// right_frame, with the sample rig's calibration and the given publish_encoding, until a pair
// with sequence number last_seq or later was published (the check of the first pair runs before
// it is written).
EyeOrderReport run_eye_order(uint32_t fourcc, const std::vector<uint8_t>& left_frame,
                             const std::vector<uint8_t>& right_frame,
                             const std::string& publish_encoding, uint64_t last_seq = 1) {
  const auto camera = [fourcc] {
    auto cam = std::make_shared<FakeCamera>();
    SizeOffer s;
    s.min_width_px = s.max_width_px = 640;
    s.min_height_px = s.max_height_px = 480;
    s.rates_hz = {30.0};
    cam->formats = {{fourcc, fourcc == kFourccMjpeg ? "Motion-JPEG" : "YUYV 4:2:2", {s}}};
    return cam;
  };
  auto left = camera(), right = camera();
  CameraServerParams params = rig_params();
  params.width_px = 640;
  params.height_px = 480;
  params.pixel_format = fourcc == kFourccMjpeg ? "mjpeg" : "yuyv";
  params.publish_encoding = publish_encoding;
  params.calibration_file =
      stereoball::testing::source_path("config/calibration/opencv_samples_stereo.yaml");
  node::CommonOptions options;
  options.domain_id = stereoball::testing::test_domain();
  options.partition = stereoball::testing::unique_partition();
  node::Runner runner("camera_server", options);
  dds::DataReader<stereoball_msg_StereoFrame> frames(runner.participant(), topics::kStereoFrame);
  auto node = CameraServerNode::create(params, runner, factory(left, right));
  EyeOrderReport report;
  if (!node) {
    report.last_error = node.error();
    return report;
  }
  std::thread loop([&] { runner.run(); });
  // (pairs queued only once the node exists: its start-up warnings come before any frame's)
  int64_t stamp_ns = 100'000'000'000;
  report.published = stereoball::testing::eventually(
      [&] {
        for (int i = 0; i < 10 && left->queued() == 0 && right->queued() == 0; ++i) {
          stamp_ns += kPeriodNs;
          left->push({stamp_ns, left_frame, 0});
          right->push({stamp_ns + 1'000'000, right_frame, 0});
        }
        bool last = false;
        for (auto& f : frames.take()) {
          report.encoding = f->encoding ? f->encoding : "";
          last = last || f->seq >= last_seq;
        }
        return last;
      },
      30s);
  runner.stop();
  loop.join();
  node->reset();
  report.eyes_swapped = runner.health().counter("eyes_swapped");
  report.eye_order = runner.health().counter("eye_order");
  report.last_error = runner.health().snapshot(node::monotonic_ns()).last_error;
  return report;
}

// Cameras plugged the other way round (the sample rig's right image on the left camera),
// published as captured and (the reference) as bgr8: both say the images look swapped, in the
// same words (the check sees the pixels bgr8 carries: the same conversion or decoder).
void expect_swap_reported_as_for_bgr8(uint32_t fourcc, const std::string& native_encoding) {
  const auto left = sample_frame("left03.jpg", fourcc), right = sample_frame("right03.jpg", fourcc);
  ASSERT_FALSE(left.empty() || right.empty());
  const EyeOrderReport native = run_eye_order(fourcc, right, left, "native");
  const EyeOrderReport bgr8 = run_eye_order(fourcc, right, left, "bgr8");
  ASSERT_TRUE(native.published) << native.last_error;
  ASSERT_TRUE(bgr8.published) << bgr8.last_error;
  EXPECT_EQ(native.encoding, native_encoding);
  EXPECT_EQ(bgr8.encoding, "bgr8");
  EXPECT_GE(native.eyes_swapped, 1u) << native.last_error;
  EXPECT_GE(bgr8.eyes_swapped, 1u) << bgr8.last_error;
  EXPECT_NE(native.last_error.find("look swapped"), std::string::npos) << native.last_error;
  EXPECT_NE(native.last_error.find("swap left_device and right_device"), std::string::npos);
  EXPECT_EQ(native.last_error, bgr8.last_error);
}

TEST(CameraServerEyeOrder, GivenSwappedYuyvCamerasWhenPublishedNativeThenReportedAsForBgr8) {
  expect_swap_reported_as_for_bgr8(kFourccYuyv, "yuyv");
}

TEST(CameraServerEyeOrder, GivenSwappedMjpegCamerasWhenPublishedNativeThenReportedAsForBgr8) {
  expect_swap_reported_as_for_bgr8(kFourccMjpeg, "jpeg");
}

TEST(CameraServerEyeOrder, GivenYuyvCamerasInOrderWhenPublishedNativeThenNoSwapReported) {
  // Given the sample rig's cameras in order, both YUYV, published as captured
  const auto left = sample_frame("left03.jpg", kFourccYuyv);
  const auto right = sample_frame("right03.jpg", kFourccYuyv);
  ASSERT_FALSE(left.empty() || right.empty());
  const EyeOrderReport native = run_eye_order(kFourccYuyv, left, right, "native");
  // Then the frames are yuyv and the check (done before the first was written) says nothing
  ASSERT_TRUE(native.published) << native.last_error;
  EXPECT_EQ(native.encoding, "yuyv");
  EXPECT_EQ(native.eyes_swapped, 0u) << native.last_error;
  EXPECT_EQ(native.last_error.find("eye order"), std::string::npos) << native.last_error;
}

TEST(CameraServerEyeOrder,
     GivenMjpegThatNeverDecodesWhenPublishedNativeThenReportedOnceThenGivenUp) {
  // Given MJPEG cameras whose frames start as a JPEG but cannot be decoded, published as
  // captured (every frame is still published: only the check needs the pixels)
  std::vector<uint8_t> broken(4096, 0x5A);
  broken[0] = 0xFF;
  broken[1] = 0xD8;
  // When 600 pairs stream (the watch samples every 100th frame, at most 5 times)
  const EyeOrderReport native = run_eye_order(kFourccMjpeg, broken, broken, "native", 600);
  // Then the cause is reported once, then that the check was given up (not once per 100th
  // frame for ever), and no verdict on the order
  ASSERT_TRUE(native.published) << native.last_error;
  EXPECT_EQ(native.encoding, "jpeg");
  EXPECT_EQ(native.eye_order, 2u) << native.last_error;
  EXPECT_EQ(native.eyes_swapped, 0u);
  EXPECT_EQ(native.last_error.rfind("eye order not checked (check given up): left eye: ", 0), 0u)
      << native.last_error;
}

}  // namespace
}  // namespace stereoball::camera_server
