#include "motion_controller/node/command_msg.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

namespace stereoball::motion_controller {
namespace {

TEST(CommandConversion, GivenFollowingTrack_ThenFieldsMapped) {
  stereoball_msg_BallTrack m{};
  m.state = stereoball_msg_TRACK_FOLLOWING;
  m.position_valid = true;
  m.bearing_rad = -0.3;
  m.distance_m = 1.7;
  m.last_seen_side = stereoball_msg_SIDE_LEFT;
  m.capture_stamp_ns = 500;
  m.last_accepted_stamp_ns = 400;
  const TrackSample t = to_sample(m);
  EXPECT_EQ(t.state, TrackState::kFollowing);
  EXPECT_TRUE(t.position_valid);
  EXPECT_EQ(t.bearing_rad, -0.3);
  EXPECT_EQ(t.distance_m, 1.7);
  EXPECT_EQ(t.last_seen_side, Side::kLeft);
  EXPECT_EQ(t.capture_stamp_ns, 500);
  EXPECT_EQ(t.last_accepted_stamp_ns, 400);
}

TEST(CommandConversion, GivenPositionAndVelocity_ThenBearingAndRangeRates) {
  // Ball 2 m ahead moving right at 0.5 m/s and away at 0.2 m/s
  stereoball_msg_BallTrack m{};
  m.state = stereoball_msg_TRACK_FOLLOWING;
  m.position_valid = true;
  m.distance_m = 2.0;
  m.position_m[2] = 2.0;
  m.velocity_mps[0] = 0.5;
  m.velocity_mps[2] = 0.2;
  const TrackSample t = to_sample(m);
  EXPECT_NEAR(t.bearing_rate_radps, 0.25, 1e-12);  // vx / z
  EXPECT_NEAR(t.distance_rate_mps, 0.2, 1e-12);
}

TEST(CommandConversion, GivenStatesAndSides_ThenEachMapped) {
  stereoball_msg_BallTrack m{};
  m.state = stereoball_msg_TRACK_SEARCHING;
  m.last_seen_side = stereoball_msg_SIDE_RIGHT;
  EXPECT_EQ(to_sample(m).state, TrackState::kSearching);
  EXPECT_EQ(to_sample(m).last_seen_side, Side::kRight);
  m.state = stereoball_msg_TRACK_IDLE;
  m.last_seen_side = stereoball_msg_SIDE_UNKNOWN;
  EXPECT_EQ(to_sample(m).state, TrackState::kIdle);
  EXPECT_EQ(to_sample(m).last_seen_side, Side::kUnknown);
}

TEST(CommandConversion, GivenNonFiniteBearing_ThenPositionInvalid) {
  stereoball_msg_BallTrack m{};
  m.state = stereoball_msg_TRACK_FOLLOWING;
  m.position_valid = true;
  m.bearing_rad = std::nan("");
  m.distance_m = 1.0;
  const TrackSample t = to_sample(m);
  EXPECT_FALSE(t.position_valid);
  EXPECT_EQ(t.bearing_rad, 0.0);
}

TEST(CommandConversion, GivenCommand_ThenMessageCarriesItWithSource) {
  Command c;
  c.linear_mps = 0.25;
  c.angular_radps = -0.5;
  stereoball_msg_VelocityCommand m{};
  to_message(c, 9, 1234, m);
  EXPECT_EQ(m.seq, 9u);
  EXPECT_EQ(m.stamp_ns, 1234);
  EXPECT_EQ(m.linear_mps, 0.25);
  EXPECT_EQ(m.angular_radps, -0.5);
  EXPECT_STREQ(m.source, "motion_controller");
}

TEST(CommandConversion, GivenExposureStamps_ThenTrackToCommandKeepsThemUnchanged) {
  // Given a track of a frame whose stamp needs all 64 bits
  const std::int64_t stamp = 1'733'123'456'789'012'345;
  stereoball_msg_BallTrack m{};
  m.capture_stamp_ns = stamp;
  m.last_accepted_stamp_ns = stamp - 1;
  // Then the core sample and the command answering it carry it unchanged
  const TrackSample t = to_sample(m);
  EXPECT_EQ(t.capture_stamp_ns, stamp);
  EXPECT_EQ(t.last_accepted_stamp_ns, stamp - 1);
  Command c;
  c.capture_stamp_ns = t.capture_stamp_ns;
  stereoball_msg_VelocityCommand out{};
  to_message(c, 1, stamp + 8'000'000, out);
  EXPECT_EQ(out.capture_stamp_ns, stamp);
}

}  // namespace
}  // namespace stereoball::motion_controller
