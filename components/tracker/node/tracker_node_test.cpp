// Integration test: the real tracker process on a private domain, fed a
// scripted ball/detection sequence; checks the published ball/track.

#include <gtest/gtest.h>
#include <signal.h>

#include <cmath>
#include <fstream>
#include <optional>
#include <thread>

#include "common/dds/reader.hpp"
#include "common/dds/writer.hpp"
#include "process.hpp"

namespace sb = stereoball;
using namespace std::chrono_literals;
using sb::testing::Process;

namespace {

constexpr std::int64_t kFrameNs = 33'333'333;

// A disc of colour (r, g, b) on grey, as the detector's 21x21 patch would show a ball.
void fill_patch(stereoball_msg_BallDetection& m, int r, int g, int b) {
  for (int y = 0; y < 21; ++y) {
    for (int x = 0; x < 21; ++x) {
      const bool in = (x - 10) * (x - 10) + (y - 10) * (y - 10) <= 81;
      const int c[3] = {in ? r : 110, in ? g : 110, in ? b : 110};
      for (int ch = 0; ch < 3; ++ch)
        m.patch_rgb[(y * 21 + x) * 3 + ch] = static_cast<uint8_t>(c[ch]);
    }
  }
  m.patch_valid = true;
}

class TrackerNodeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    partition_ = sb::testing::unique_partition();
    tracker_.emplace(Process::start(
        {sb::testing::bin("tracker"), "--config", sb::testing::source_path("config/tracker.yaml"),
         "--domain", std::to_string(sb::testing::test_domain()), "--partition", partition_}));
    participant_.emplace(sb::dds::ParticipantOptions{sb::testing::test_domain(), partition_});
    writer_.emplace(*participant_, sb::topics::kBallDetection);
    reader_.emplace(*participant_, sb::topics::kBallTrack);
    ASSERT_TRUE(writer_->wait_for_readers(1, 10'000'000'000)) << tracker_->output();
    ASSERT_TRUE(reader_->wait_for_writers(1, 10'000'000'000)) << tracker_->output();
  }

  // Publishes one detection and waits for the track of that frame.
  stereoball_msg_BallTrack send(stereoball_msg_BallDetection m) {
    m.frame_seq = ++seq_;
    m.capture_stamp_ns = stamp_ns_ += kFrameNs;
    writer_->write(m);
    std::optional<stereoball_msg_BallTrack> got;
    sb::testing::eventually(
        [&] {
          for (auto& s : reader_->take()) {
            if (s->frame_seq == seq_) {
              got = *s;
              reason_ = s->reason ? s->reason : "";
            }
          }
          return got.has_value();
        },
        5s);
    EXPECT_TRUE(got.has_value()) << "no ball/track for frame " << seq_ << "\n"
                                 << tracker_->output();
    return got.value_or(stereoball_msg_BallTrack{});
  }

  stereoball_msg_BallTrack ball(double x, double y, double z, int r, int g, int b) {
    stereoball_msg_BallDetection m{};
    m.status = stereoball_msg_DETECTION_FOUND;
    m.position_m[0] = x;
    m.position_m[1] = y;
    m.position_m[2] = z;
    m.left.x_px = static_cast<float>(320.0 + 500.0 * x / z);
    fill_patch(m, r, g, b);
    return send(m);
  }

  stereoball_msg_BallTrack nothing() {
    stereoball_msg_BallDetection m{};
    m.status = stereoball_msg_DETECTION_NO_CANDIDATE;
    return send(m);
  }

  std::string partition_;
  std::optional<Process> tracker_;
  std::optional<sb::dds::DomainParticipant> participant_;
  std::optional<sb::dds::DataWriter<stereoball_msg_BallDetection>> writer_;
  std::optional<sb::dds::DataReader<stereoball_msg_BallTrack>> reader_;
  std::uint64_t seq_ = 0;
  std::int64_t stamp_ns_ = 1'700'000'000'000'000'000;
  std::string reason_;
};

TEST_F(TrackerNodeTest, GivenScriptedDetections_ThenIdleFollowingSearchingFollowingRight) {
  // Startup: five positions collected, the sixth accepted
  for (int i = 0; i < 5; ++i) {
    const auto tr = ball(0.3, 0.0, 2.0, 220, 40, 30);
    ASSERT_EQ(tr.state, stereoball_msg_TRACK_IDLE);
    ASSERT_EQ(tr.verdict, stereoball_msg_VERDICT_STARTUP_COLLECTING);
    ASSERT_FALSE(tr.position_valid);
  }
  auto tr = ball(0.3, 0.0, 2.0, 220, 40, 30);
  ASSERT_EQ(tr.verdict, stereoball_msg_VERDICT_STARTUP_ACCEPTED) << reason_;
  ASSERT_EQ(tr.state, stereoball_msg_TRACK_FOLLOWING);
  EXPECT_TRUE(tr.position_valid);
  EXPECT_NEAR(tr.position_m[0], 0.3, 1e-9);
  EXPECT_NEAR(tr.bearing_rad, std::atan2(0.3, 2.0), 1e-9);
  EXPECT_EQ(tr.capture_stamp_ns, stamp_ns_);
  EXPECT_EQ(tr.last_accepted_stamp_ns, stamp_ns_);

  // Rolling right at 1.2 m/s until it leaves the image: block matching accepts
  double x = 0.3;
  while (x < 1.25) {
    x += 0.04;
    tr = ball(x, 0.0, 2.0, 220, 40, 30);
    ASSERT_EQ(tr.verdict, stereoball_msg_VERDICT_BLOCK_MATCH_ACCEPTED) << reason_;
    EXPECT_EQ(tr.ssd, 0.0);
  }
  EXPECT_GT(tr.velocity_mps[0], 0.8);

  // Out of view: searching toward the right
  for (int i = 0; i < 8; ++i) tr = nothing();
  ASSERT_EQ(tr.state, stereoball_msg_TRACK_SEARCHING);
  EXPECT_EQ(tr.verdict, stereoball_msg_VERDICT_NO_DETECTION);
  EXPECT_EQ(tr.last_seen_side, stereoball_msg_SIDE_RIGHT);

  // Reappears darker: block matching fails, statistics accept after five positions
  int frames = 0;
  do {
    tr = ball(0.8 - 0.01 * frames, 0.05, 1.6, 120, 20, 15);
    ++frames;
    ASSERT_LE(frames, 6) << reason_;
  } while (tr.state != stereoball_msg_TRACK_FOLLOWING);
  EXPECT_EQ(tr.verdict, stereoball_msg_VERDICT_STATISTICS_ACCEPTED);
  EXPECT_GT(tr.ssd, 200000.0);
  EXPECT_EQ(tr.last_seen_side, stereoball_msg_SIDE_RIGHT);
}

TEST_F(TrackerNodeTest, GivenBallLeavingLeft_ThenSearchingLeft) {
  for (int i = 0; i < 6; ++i) ball(-0.2, 0.0, 2.0, 30, 30, 220);
  double x = -0.2;
  stereoball_msg_BallTrack tr{};
  while (x > -1.25) {
    x -= 0.04;
    tr = ball(x, 0.0, 2.0, 30, 30, 220);
    ASSERT_EQ(tr.state, stereoball_msg_TRACK_FOLLOWING);
  }
  for (int i = 0; i < 8; ++i) tr = nothing();
  EXPECT_EQ(tr.state, stereoball_msg_TRACK_SEARCHING);
  EXPECT_EQ(tr.last_seen_side, stereoball_msg_SIDE_LEFT);
}

TEST_F(TrackerNodeTest, GivenMalformedDetection_ThenNodeKeepsAnswering) {
  stereoball_msg_BallDetection bad{};
  bad.status = stereoball_msg_DETECTION_FOUND;
  bad.position_m[2] = std::nan("");
  const auto tr = send(bad);
  EXPECT_EQ(tr.verdict, stereoball_msg_VERDICT_NO_DETECTION);
  // The next good detection is processed normally
  EXPECT_EQ(ball(0.0, 0.0, 1.0, 200, 200, 0).verdict, stereoball_msg_VERDICT_STARTUP_COLLECTING);
  EXPECT_TRUE(tracker_->running());
}

TEST_F(TrackerNodeTest, GivenGarbageFrameWithOldStamp_ThenTrackKeepsFollowing) {
  // Given a followed ball
  for (int i = 0; i < 6; ++i) ball(0.1, 0.0, 2.0, 220, 40, 30);
  // When a frame the detector could not read arrives with a stamp 10 s in the past (a garbage
  // stereo/frame sample carries any stamp)
  stereoball_msg_BallDetection garbage{};
  garbage.status = stereoball_msg_DETECTION_BAD_FRAME;
  garbage.frame_seq = 999'999;
  garbage.capture_stamp_ns = stamp_ns_ - 10'000'000'000;
  writer_->write(garbage);
  // Then the next real frame continues the track instead of starting over
  const auto tr = ball(0.12, 0.0, 2.0, 220, 40, 30);
  EXPECT_EQ(tr.state, stereoball_msg_TRACK_FOLLOWING) << reason_;
  EXPECT_EQ(tr.verdict, stereoball_msg_VERDICT_BLOCK_MATCH_ACCEPTED) << reason_;
  EXPECT_EQ(tracker_->output().find("jumped back"), std::string::npos) << tracker_->output();
}

// Issue 22: detections at (1e5, y, 1e6) m were accepted and the robot drove toward them.
TEST_F(TrackerNodeTest, GivenDetectionsBeyondMaxRange_ThenRefusedAndNeverFollowed) {
  for (int i = 0; i < 8; ++i) {
    const auto sent = std::chrono::steady_clock::now();
    const auto tr = ball(1e5, 0.1, 1e6, 220, 40, 30);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - sent).count();
    if (i == 0) std::printf("[figure] far detection answered in %.1f ms (round trip)\n", ms);
    ASSERT_EQ(tr.verdict, stereoball_msg_VERDICT_REJECTED) << reason_;
    ASSERT_EQ(tr.state, stereoball_msg_TRACK_IDLE);
    ASSERT_FALSE(tr.position_valid);
  }
  EXPECT_NE(reason_.find("beyond max_range_m 20 m"), std::string::npos) << reason_;
  EXPECT_EQ(ball(0.0, 0.0, 1.0, 200, 200, 0).verdict, stereoball_msg_VERDICT_STARTUP_COLLECTING);
}

TEST_F(TrackerNodeTest, GivenSigterm_ThenExitsZero) {
  tracker_->signal(SIGTERM);
  EXPECT_EQ(tracker_->wait_for_exit(5s), 0) << tracker_->output();
}

TEST(TrackerNodeCli, GivenBadConfig_ThenOneClearLineAndNonZeroExit) {
  const std::string dir = sb::testing::temp_dir();
  std::ofstream(dir + "/bad.yaml") << "ssd_threshold: -5\n";
  const auto [code, out] =
      sb::testing::run({sb::testing::bin("tracker"), "--config", dir + "/bad.yaml"}, 10s);
  EXPECT_NE(code, 0);
  EXPECT_NE(out.find("ssd_threshold"), std::string::npos) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
}

TEST(TrackerNodeCli, GivenHelp_ThenDescribesTopicsAndExitsZero) {
  const auto [code, out] = sb::testing::run({sb::testing::bin("tracker"), "--help"}, 10s);
  EXPECT_EQ(code, 0);
  EXPECT_NE(out.find("ball/track"), std::string::npos) << out;
  EXPECT_NE(out.find("--config"), std::string::npos) << out;
}

}  // namespace
