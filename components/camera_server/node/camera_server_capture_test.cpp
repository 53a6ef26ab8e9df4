// The camera_server node streaming from cameras (scripted ones): its capture thread pairs and
// publishes the frames while the runner's loop publishes health, and its preview worker
// encodes previews for a reader. Run under ThreadSanitizer (tools/tsan_tests.sh) this is the
// capture thread's race check.

#include <gtest/gtest.h>

#include <algorithm>
#include <thread>

#include "camera_server/io/fake_rig.hpp"
#include "camera_server/node/camera_server_node.hpp"
#include "common/dds/reader.hpp"
#include "process.hpp"

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

}  // namespace
}  // namespace stereoball::camera_server
