#include "tracker/node/track_msg.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace stereoball::tracker {
namespace {

stereoball_msg_BallDetection found_at(double x, double y, double z) {
  stereoball_msg_BallDetection m{};
  m.status = stereoball_msg_DETECTION_FOUND;
  m.position_m[0] = x;
  m.position_m[1] = y;
  m.position_m[2] = z;
  m.left.x_px = 500.0f;
  m.patch_valid = true;
  for (std::size_t i = 0; i < kPatchBytes; ++i) m.patch_rgb[i] = static_cast<std::uint8_t>(i % 251);
  return m;
}

TEST(TrackConversion, GivenFoundDetection_ThenPositionPixelWidthAndPatchCopied) {
  const auto c = to_detection(found_at(0.4, -0.1, 2.5), 640);
  ASSERT_FALSE(c.problem.has_value());
  EXPECT_TRUE(c.detection.found);
  EXPECT_EQ(c.detection.position_m, Eigen::Vector3d(0.4, -0.1, 2.5));
  EXPECT_EQ(c.detection.left_x_px, 500.0);
  EXPECT_EQ(c.detection.image_width_px, 640u);
  EXPECT_TRUE(c.detection.patch_valid);
  EXPECT_EQ(c.detection.patch_rgb[0], 0);
  EXPECT_EQ(c.detection.patch_rgb[kPatchBytes - 1], (kPatchBytes - 1) % 251);
}

TEST(TrackConversion, GivenStatusOtherThanFound_ThenNotFoundAndNoProblem) {
  auto m = found_at(0.4, 0, 2);
  m.status = stereoball_msg_DETECTION_EPIPOLAR_MISMATCH;
  const auto c = to_detection(m, 640);
  EXPECT_FALSE(c.detection.found);
  EXPECT_FALSE(c.problem.has_value());
}

TEST(TrackConversion, GivenFoundWithBadPosition_ThenNotFoundAndProblemReported) {
  for (const double z : {std::nan(""), 0.0, -1.0, std::numeric_limits<double>::infinity()}) {
    const auto c = to_detection(found_at(0.1, 0.0, z), 640);
    EXPECT_FALSE(c.detection.found) << z;
    ASSERT_TRUE(c.problem.has_value()) << z;
    EXPECT_NE(c.problem->find("position"), std::string::npos);
  }
}

TEST(TrackConversion, GivenTrack_ThenEveryFieldMapped) {
  Track t;
  t.state = TrackState::kSearching;
  t.verdict = Verdict::kStatisticsAccepted;
  t.reason = "because";
  t.position_valid = true;
  t.position_m = {1, 2, 3};
  t.velocity_mps = {0.1, 0.2, 0.3};
  t.bearing_rad = 0.25;
  t.distance_m = 3.1;
  t.last_seen_side = Side::kLeft;
  t.ssd = 1234.0;
  t.last_accepted_stamp_ns = 77;
  stereoball_msg_BallTrack m{};
  to_message(t, 42, 1000, 2000, m);
  EXPECT_EQ(m.frame_seq, 42u);
  EXPECT_EQ(m.capture_stamp_ns, 1000);
  EXPECT_EQ(m.publish_stamp_ns, 2000);
  EXPECT_EQ(m.state, stereoball_msg_TRACK_SEARCHING);
  EXPECT_EQ(m.verdict, stereoball_msg_VERDICT_STATISTICS_ACCEPTED);
  EXPECT_STREQ(m.reason, "because");
  EXPECT_TRUE(m.position_valid);
  EXPECT_EQ(m.position_m[2], 3.0);
  EXPECT_EQ(m.velocity_mps[1], 0.2);
  EXPECT_EQ(m.bearing_rad, 0.25);
  EXPECT_EQ(m.distance_m, 3.1);
  EXPECT_EQ(m.last_seen_side, stereoball_msg_SIDE_LEFT);
  EXPECT_EQ(m.ssd, 1234.0);
  EXPECT_EQ(m.last_accepted_stamp_ns, 77);
}

TEST(TrackConversion, GivenEachVerdict_ThenDistinctMessageVerdicts) {
  const Verdict all[] = {
      Verdict::kNoDetection,     Verdict::kStartupCollecting,  Verdict::kStartupInconsistent,
      Verdict::kStartupAccepted, Verdict::kBlockMatchAccepted, Verdict::kStatisticsAccepted,
      Verdict::kRejected};
  const stereoball_msg_TrackVerdict expected[] = {stereoball_msg_VERDICT_NO_DETECTION,
                                                  stereoball_msg_VERDICT_STARTUP_COLLECTING,
                                                  stereoball_msg_VERDICT_STARTUP_INCONSISTENT,
                                                  stereoball_msg_VERDICT_STARTUP_ACCEPTED,
                                                  stereoball_msg_VERDICT_BLOCK_MATCH_ACCEPTED,
                                                  stereoball_msg_VERDICT_STATISTICS_ACCEPTED,
                                                  stereoball_msg_VERDICT_REJECTED};
  for (int i = 0; i < 7; ++i) {
    Track t;
    t.verdict = all[i];
    stereoball_msg_BallTrack m{};
    to_message(t, 0, 0, 0, m);
    EXPECT_EQ(m.verdict, expected[i]) << i;
  }
}

}  // namespace
}  // namespace stereoball::tracker
