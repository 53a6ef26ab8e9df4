#include "camera_server/io/stereo_capture.hpp"

#include <gtest/gtest.h>

#include <cerrno>

#include "camera_server/io/fake_rig.hpp"

namespace stereoball::camera_server {
namespace {

using namespace testing;

constexpr int64_t kS = 1'000'000'000;

bool any_line_has(const std::vector<std::string>& lines, const std::string& part) {
  for (const auto& l : lines) {
    if (l.find(part) != std::string::npos) return true;
  }
  return false;
}

// Polls until no more pairs arrive, collecting them.
std::vector<RawStereoPair> run(StereoCapture& cap, int64_t now_ns, int rounds = 20) {
  std::vector<RawStereoPair> all;
  for (int i = 0; i < rounds; ++i) {
    auto got = cap.poll_once(0, now_ns);
    for (auto& p : got) all.push_back(std::move(p));
  }
  return all;
}

TEST(StereoCapture, GivenTwoCamerasWithMatchingStampsWhenPolledThenRawPairsInOrder) {
  auto l = make_camera();
  auto r = make_camera();
  for (int i = 0; i < 5; ++i) {
    l->push(yuyv_frame(100 * kS + i * kPeriodNs, static_cast<uint8_t>(i)));
    r->push(yuyv_frame(100 * kS + i * kPeriodNs + 3'000'000, static_cast<uint8_t>(50 + i)));
  }
  StereoCapture cap(rig_params(), factory(l, r));
  const DeviceStatus s = cap.start();
  ASSERT_TRUE(s.ok()) << s.message;
  const auto pairs = run(cap, 0);
  ASSERT_EQ(pairs.size(), 5u);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(pairs[i].seq, static_cast<uint64_t>(i));
    EXPECT_EQ(pairs[i].left.bytes[0], i);
    EXPECT_EQ(pairs[i].right.bytes[0], 50 + i);
    EXPECT_EQ(pairs[i].left.fourcc, kFourccYuyv);
    EXPECT_EQ(pairs[i].left.step_bytes, 2 * kW);
    EXPECT_EQ(pairs[i].left.bytes.size(), size_t{2} * kW * kH);
  }
  EXPECT_TRUE(cap.healthy());
}

TEST(StereoCapture, GivenShortAndCorruptFramesWhenPolledThenCountedNotPaired) {
  auto l = make_camera();
  auto r = make_camera();
  FakeFrameScript short_frame = yuyv_frame(0, 1);
  short_frame.bytes.resize(10);
  l->push(short_frame);
  r->push(yuyv_frame(0, 2));
  StereoCapture cap(rig_params(), factory(l, r));
  ASSERT_TRUE(cap.start().ok());
  EXPECT_TRUE(run(cap, 0).empty());
  EXPECT_EQ(cap.health().eyes[0].corrupted, 1u);
}

TEST(StereoCapture, GivenRightUnpluggedMidStreamWhenPolledThenKeepsRunningAndReopensWithBackoff) {
  auto l = make_camera();
  auto r = make_camera();
  r->failed_opens_after_unplug = 2;
  CameraServerParams params = rig_params();
  params.stall_timeout_s = 60.0;  // the left camera is silent in this script; not the point here
  for (int i = 0; i < 3; ++i) {
    l->push(yuyv_frame(i * kPeriodNs, static_cast<uint8_t>(i)));
    r->push(yuyv_frame(i * kPeriodNs, static_cast<uint8_t>(i)));
  }
  FakeFrameScript unplug;
  unplug.err = ENODEV;
  r->push(unplug);
  StereoCapture cap(params, factory(l, r));
  ASSERT_TRUE(cap.start().ok());

  // Given the first three pairs, when the right camera vanishes at t = 10 s
  EXPECT_EQ(run(cap, 10 * kS).size(), 3u);
  EXPECT_FALSE(cap.healthy());
  auto log = cap.take_log();
  EXPECT_TRUE(any_line_has(log, "right camera lost")) << (log.empty() ? "" : log[0]);
  EXPECT_TRUE(any_line_has(log, "disconnected"));
  EXPECT_TRUE(any_line_has(log, "reopening in 0.5 s"));
  const int opens_after_loss = r->opens;

  // Then no reopen before the back-off elapses
  run(cap, 10 * kS + kS / 4);
  EXPECT_EQ(r->opens, opens_after_loss);
  // Then two attempts fail (camera still unplugged) with growing waits
  run(cap, 10 * kS + kS / 2);
  EXPECT_EQ(r->opens, opens_after_loss + 1);
  log = cap.take_log();
  EXPECT_TRUE(any_line_has(log, "next attempt in 1.0 s"));
  run(cap, 10 * kS + kS / 2 + kS);
  log = cap.take_log();
  EXPECT_TRUE(any_line_has(log, "next attempt in 2.0 s"));
  EXPECT_FALSE(cap.healthy());
  // Then the third attempt succeeds and pairs flow again
  run(cap, 10 * kS + kS / 2 + 3 * kS);
  EXPECT_TRUE(cap.healthy());
  log = cap.take_log();
  EXPECT_TRUE(any_line_has(log, "reopened after 3 attempt(s)"));
  l->push(yuyv_frame(20 * kS, 9));
  r->push(yuyv_frame(20 * kS + 1'000, 9));
  const auto pairs = run(cap, 20 * kS);
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0].left.bytes[0], 9);
  const CaptureHealth h = cap.health();
  EXPECT_EQ(h.eyes[1].errors, 1u);
  EXPECT_EQ(h.eyes[1].reopens, 1u);
  EXPECT_EQ(h.eyes[0].errors, 0u);
}

TEST(StereoCapture, GivenCameraSilentWithoutErrorWhenStallTimeoutPassesThenLostAndReopened) {
  auto l = make_camera();
  auto r = make_camera();
  StereoCapture cap(rig_params(), factory(l, r));  // stall_timeout_s = 2
  ASSERT_TRUE(cap.start().ok());
  l->push(yuyv_frame(0, 1));
  run(cap, 0);
  run(cap, 1 * kS);
  l->push(yuyv_frame(1 * kS, 1));
  run(cap, 1 * kS);
  EXPECT_TRUE(cap.healthy());
  run(cap, 2 * kS + kS / 10);  // right: 2.1 s of silence; left: 1.1 s
  EXPECT_FALSE(cap.health().eyes[1].streaming);
  EXPECT_TRUE(cap.health().eyes[0].streaming);
  const auto log = cap.take_log();
  ASSERT_FALSE(log.empty());
  EXPECT_TRUE(any_line_has(log, "right camera lost: /fake/right: no frame for 2.1 s")) << log[0];
  run(cap, 3 * kS);  // back-off 0.5 s elapsed: reopened
  EXPECT_TRUE(cap.health().eyes[1].streaming);
  EXPECT_EQ(r->opens, 2);
}

TEST(StereoCapture, GivenLeftMissingAtStartWhenStartedThenOneLineNamesEyeAndCause) {
  auto l = make_camera();
  l->open_errno = ENOENT;
  StereoCapture cap(rig_params(), factory(l, make_camera()));
  const DeviceStatus s = cap.start();
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.message.rfind("left camera: /fake/left", 0), 0u) << s.message;
  EXPECT_NE(s.message.find("no such device"), std::string::npos);
  EXPECT_EQ(s.message.find('\n'), std::string::npos);
}

TEST(StereoCapture, GivenSameDeviceTwiceWhenStartedThenRefusedBeforeOpening) {
  auto cam = make_camera();
  CameraServerParams p = rig_params();
  p.right_device = p.left_device;
  StereoCapture cap(p, factory(cam, cam));
  const DeviceStatus s = cap.start();
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message.find("same device"), std::string::npos);
  EXPECT_EQ(cam->opens, 0);
}

TEST(StereoCapture, GivenOneCameraStallsWhenPolledThenUnpairedFramesAreDroppedAndCounted) {
  auto l = make_camera();
  auto r = make_camera();
  for (int i = 0; i < 10; ++i) l->push(yuyv_frame(i * kPeriodNs, 0));
  r->push(yuyv_frame(9 * kPeriodNs, 0));
  StereoCapture cap(rig_params(), factory(l, r));
  ASSERT_TRUE(cap.start().ok());
  run(cap, 0);
  const CaptureHealth h = cap.health();
  EXPECT_EQ(h.pairing.pairs, 1u);
  EXPECT_EQ(h.pairing.dropped_left, 9u);
}

}  // namespace
}  // namespace stereoball::camera_server
