#include "viewer/bridge/view_msg.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>

namespace stereoball::viewer {
namespace {

TEST(Conversion, DetectionKeepsCirclesReasonAndLatency) {
  stereoball_msg_BallDetection m{};
  m.frame_seq = 12;
  m.capture_stamp_ns = 1'000'000'000;
  m.publish_stamp_ns = 1'004'000'000;
  m.status = stereoball_msg_DETECTION_EPIPOLAR_MISMATCH;
  char reason[] = "rows 9 px apart";
  m.reason = reason;
  m.left = {10, 20, 5, 0.5f};
  const Detection d = to_view(m);
  EXPECT_EQ(d.frame_seq, 12u);
  EXPECT_FALSE(d.found);
  EXPECT_EQ(d.status, "epipolar_mismatch");
  EXPECT_EQ(d.reason, "rows 9 px apart");
  EXPECT_EQ(d.left.radius_px, 5);
  EXPECT_DOUBLE_EQ(d.latency_ms, 4.0);
}

TEST(Conversion, TrackNamesStateVerdictSideAndAcceptance) {
  stereoball_msg_BallTrack m{};
  m.state = stereoball_msg_TRACK_SEARCHING;
  m.verdict = stereoball_msg_VERDICT_STATISTICS_ACCEPTED;
  m.last_seen_side = stereoball_msg_SIDE_RIGHT;
  m.reason = nullptr;  // a missing string must not crash
  const Track t = to_view(m);
  EXPECT_EQ(t.state, "searching");
  EXPECT_EQ(t.verdict, "statistics_accepted");
  EXPECT_TRUE(t.accepted);
  EXPECT_EQ(t.last_seen_side, "right");
  EXPECT_EQ(t.reason, "");
  const std::int32_t out_of_range = 77;  // the bytes of a value no enumerator has
  std::memcpy(&m.state, &out_of_range, sizeof out_of_range);
  EXPECT_EQ(to_view(m).state, "unknown(77)");
}

}  // namespace
}  // namespace stereoball::viewer
