#include "tracker/core/tracker.hpp"

#include <gtest/gtest.h>

#include <random>

#include "tracker/core/tracker_test_support.hpp"

namespace stereoball::tracker {
namespace {

using testing::ball_patch;
using testing::detection_at;
using testing::kFramePeriodNs;

// Feeds detections to a tracker one frame apart.
class Script {
 public:
  explicit Script(const TrackerParams& p = TrackerParams{}) : tracker_(p) {}
  Track see(const Eigen::Vector3d& position_m, const Patch& patch) {
    return step(detection_at(position_m, patch));
  }
  Track none() { return step(Detection{}); }
  Track step(const Detection& d, std::int64_t period_ns = kFramePeriodNs) {
    now_ns_ += period_ns;
    return tracker_.step(d, now_ns_);
  }
  // Six frames of a still ball: five to collect, the sixth accepted.
  Track start_following(const Eigen::Vector3d& position_m, const Patch& patch) {
    Track t;
    for (int i = 0; i < 6; ++i) t = see(position_m, patch);
    return t;
  }
  Tracker& tracker() { return tracker_; }
  std::int64_t now_ns() const { return now_ns_; }

 private:
  Tracker tracker_;
  std::int64_t now_ns_ = 1'700'000'000'000'000'000;
};

const Patch kRed = ball_patch(230, 40, 30);

TEST(Tracker, GivenNoDetections_ThenIdleWithoutPosition) {
  Script s;
  Track t;
  for (int i = 0; i < 10; ++i) t = s.none();
  EXPECT_EQ(t.state, TrackState::kIdle);
  EXPECT_EQ(t.verdict, Verdict::kNoDetection);
  EXPECT_FALSE(t.position_valid);
  EXPECT_EQ(t.ssd, -1.0);
}

TEST(Tracker, GivenStillBall_ThenFiveCollectedAndTheSixthStartsFollowing) {
  Script s;
  const Eigen::Vector3d ball(0.2, 0.1, 1.5);
  for (int i = 0; i < 5; ++i) {
    const Track t = s.see(ball, kRed);
    EXPECT_EQ(t.verdict, Verdict::kStartupCollecting) << "frame " << i;
    EXPECT_EQ(t.state, TrackState::kIdle);
    EXPECT_FALSE(s.tracker().has_reference_block());  // no block matching at startup
  }
  const Track t = s.see(ball, kRed);
  EXPECT_EQ(t.verdict, Verdict::kStartupAccepted);
  EXPECT_EQ(t.state, TrackState::kFollowing);
  EXPECT_TRUE(s.tracker().has_reference_block());
  EXPECT_TRUE(t.position_valid);
  EXPECT_NEAR((t.position_m - ball).norm(), 0.0, 1e-12);
  EXPECT_NEAR(t.bearing_rad, std::atan2(0.2, 1.5), 1e-12);
  EXPECT_NEAR(t.distance_m, std::hypot(0.2, 1.5), 1e-12);
  EXPECT_EQ(t.last_seen_side, Side::kRight);
  EXPECT_EQ(t.last_accepted_stamp_ns, s.now_ns());
}

// Issue 22: a detection 1000 km away started the robot driving toward it.
TEST(Tracker, GivenPositionsBeyondMaxRange_ThenRefusedAndNeverFollowed) {
  Script s;
  const Eigen::Vector3d far_away(1e5, 0.1, 1e6);
  for (int i = 0; i < 10; ++i) {
    const Track t = s.see(far_away, kRed);
    EXPECT_EQ(t.verdict, Verdict::kRejected);
    EXPECT_EQ(t.state, TrackState::kIdle);
    EXPECT_EQ(t.reason, "position 1e+06 m from the camera is beyond max_range_m 20 m");
  }
  // A ball just inside the range starts the normal start-up.
  EXPECT_EQ(s.see({0.0, 0.1, 19.9}, kRed).verdict, Verdict::kStartupCollecting);
}

TEST(Tracker, GivenFollowing_WhenAPositionBeyondMaxRangeArrives_ThenItIsNotAccepted) {
  TrackerParams p;
  p.max_range_m = 5.0;
  Script s(p);
  ASSERT_EQ(s.start_following({0.0, 0.1, 1.5}, kRed).state, TrackState::kFollowing);
  const Track t = s.see({0.0, 0.1, 5.5}, kRed);
  EXPECT_EQ(t.verdict, Verdict::kRejected);
  EXPECT_NE(t.reason.find("beyond max_range_m 5 m"), std::string::npos) << t.reason;
}

TEST(Tracker, GivenStartupWithInconsistentPositions_ThenStaysIdle) {
  Script s;
  const double xs[6] = {-1.0, 0.8, 0.1, -0.4, 1.2, 0.0};
  Track t;
  for (int i = 0; i < 6; ++i) t = s.see(Eigen::Vector3d(xs[i], 0.0, 2.0 + 0.3 * i), kRed);
  EXPECT_EQ(t.verdict, Verdict::kStartupInconsistent);
  EXPECT_EQ(t.state, TrackState::kIdle);
  EXPECT_FALSE(t.position_valid);
  EXPECT_FALSE(s.tracker().has_reference_block());
}

TEST(Tracker, GivenFollowing_WhenSameBlockNextFrame_ThenBlockMatchAccepted) {
  Script s;
  s.start_following({0, 0, 2}, kRed);
  const Track t = s.see({0.01, 0, 2.01}, kRed);
  EXPECT_EQ(t.verdict, Verdict::kBlockMatchAccepted);
  EXPECT_EQ(t.ssd, 0.0);
  EXPECT_EQ(t.state, TrackState::kFollowing);
}

TEST(Tracker, GivenSlowlyBrighteningBall_ThenReferenceIsRefreshedOnEveryMatch) {
  // Given a ball whose brightness drifts 1% per frame
  Script s;
  s.start_following({0, 0, 2}, ball_patch(200, 60, 40, 1.0));
  const Patch last = ball_patch(200, 60, 40, 1.25);
  // Premise: the final block is far from the first one
  ASSERT_GE(block_ssd(ball_patch(200, 60, 40, 1.0), last), 200'000);
  // When the drift happens over 25 frames
  for (int i = 1; i <= 25; ++i) {
    const Track t = s.see({0, 0, 2}, ball_patch(200, 60, 40, 1.0 + 0.01 * i));
    // Then each frame matches its predecessor's block
    ASSERT_EQ(t.verdict, Verdict::kBlockMatchAccepted) << "frame " << i << ": " << t.reason;
    ASSERT_LT(t.ssd, 200'000.0);
  }
}

TEST(Tracker, GivenConfiguredThreshold_ThenSsdBelowMatchesAndEqualDoesNot) {
  TrackerParams p;
  p.ssd_threshold = 10'000.0;
  Script s(p);
  Patch a{};
  a.fill(100);
  s.start_following({0, 0, 2}, a);
  // When one byte differs by 99: SSD 9801 < 10000
  Patch b = a;
  b[100] = 199;
  Track t = s.see({0, 0, 2}, b);
  EXPECT_EQ(t.verdict, Verdict::kBlockMatchAccepted);
  EXPECT_EQ(t.ssd, 9801.0);
  // When the next block differs from b (the new reference) by 100: SSD 10000, no match
  Patch c = b;
  c[200] = 200;
  t = s.see({0, 0, 2}, c);
  EXPECT_EQ(t.ssd, 10'000.0);
  EXPECT_NE(t.verdict, Verdict::kBlockMatchAccepted);
  // And the statistics still accept the still ball
  EXPECT_EQ(t.verdict, Verdict::kStatisticsAccepted);
}

TEST(Tracker, GivenFollowing_WhenIdenticalBlockJumpsMetres_ThenNotAccepted) {
  Script s;
  s.start_following({0, 0, 2}, kRed);
  const Track t = s.see({1.5, 0, 3.0}, kRed);
  EXPECT_EQ(t.ssd, 0.0);
  EXPECT_EQ(t.verdict, Verdict::kRejected);
  EXPECT_NE(t.reason.find("jump"), std::string::npos);
  EXPECT_NEAR(t.position_m.z(), 2.0, 1e-12);  // the track keeps the last accepted position
}

TEST(Tracker, GivenFollowing_WhenBlockFailsAndStatisticsFail_ThenRejected) {
  Script s;
  s.start_following({0, 0, 2}, kRed);
  const Track t = s.see({0.2, 0, 2}, ball_patch(30, 200, 30));
  EXPECT_GT(t.ssd, 200'000.0);
  EXPECT_EQ(t.verdict, Verdict::kRejected);
  EXPECT_EQ(t.state, TrackState::kFollowing);  // one miss does not lose the ball
}

TEST(Tracker, GivenNoPatch_WhenFollowing_ThenStatisticsDecideAndSsdIsMinusOne) {
  Script s;
  s.start_following({0, 0, 2}, kRed);
  Detection d = detection_at({0.0, 0.0, 2.005}, kRed);
  d.patch_valid = false;
  const Track t = s.step(d);
  EXPECT_EQ(t.ssd, -1.0);
  EXPECT_EQ(t.verdict, Verdict::kStatisticsAccepted);
  EXPECT_NE(t.reason.find("no patch"), std::string::npos);
}

// The paper's sequence: idle -> following -> out of view -> searching toward the
// side of exit -> reappearance with another look -> reacquired by statistics.
void run_exit_and_reacquire(double direction) {
  Script s;
  const Eigen::Vector3d start(0.3 * direction, 0.0, 2.0);
  ASSERT_EQ(s.start_following(start, kRed).state, TrackState::kFollowing);
  // The ball rolls sideways at 1.2 m/s until it leaves the image (|x| > 1.28 m at 2 m)
  Eigen::Vector3d ball = start;
  int frames_in_view = 0;
  while (std::abs(ball.x()) < 1.25) {
    ball.x() += direction * 1.2 / 30.0;
    const Track t = s.see(ball, kRed);
    ASSERT_EQ(t.verdict, Verdict::kBlockMatchAccepted) << t.reason;
    ++frames_in_view;
  }
  ASSERT_GT(frames_in_view, 20);
  // Out of view: no detections, and some clutter the detector mistakes for it
  std::mt19937 rng(3);
  Track t;
  for (int i = 0; i < 7; ++i) {
    t = s.none();
    EXPECT_EQ(t.state, TrackState::kFollowing) << "lost after only " << i + 1 << " frames";
  }
  t = s.none();
  EXPECT_EQ(t.state, TrackState::kSearching);
  EXPECT_EQ(t.last_seen_side, direction > 0 ? Side::kRight : Side::kLeft);
  for (int i = 0; i < 10; ++i) {
    t = s.see(testing::clutter_position(rng), testing::clutter_patch(rng));
    EXPECT_EQ(t.verdict, Verdict::kRejected) << t.reason;
    EXPECT_EQ(t.state, TrackState::kSearching);
  }
  // The robot turned: the ball reappears near the same side, larger and darker
  const Patch new_look = ball_patch(150, 30, 20, 0.8, 10);
  ASSERT_GE(block_ssd(kRed, new_look), 200'000);
  Eigen::Vector3d again(0.9 * direction, 0.05, 1.6);
  int frames_to_reacquire = 0;
  do {
    again.x() -= direction * 0.3 / 30.0;
    t = s.see(again, new_look);
    ++frames_to_reacquire;
    ASSERT_LE(frames_to_reacquire, 6) << t.reason;
  } while (t.state != TrackState::kFollowing);
  EXPECT_EQ(t.verdict, Verdict::kStatisticsAccepted);
  // Four fresh positions plus one stray clutter position left out: the fifth is accepted
  EXPECT_EQ(frames_to_reacquire, 5);
  // Then block matching takes over with the refreshed reference
  again.x() -= direction * 0.01;
  t = s.see(again, new_look);
  EXPECT_EQ(t.verdict, Verdict::kBlockMatchAccepted);
  EXPECT_EQ(t.last_seen_side, direction > 0 ? Side::kRight : Side::kLeft);
}

TEST(Tracker, GivenBallLeavesToTheRight_ThenSearchesRightAndReacquires) {
  run_exit_and_reacquire(+1.0);
}

TEST(Tracker, GivenBallLeavesToTheLeft_ThenSearchesLeftAndReacquires) {
  run_exit_and_reacquire(-1.0);
}

TEST(Tracker, GivenLowFrameRate_WhenNoAcceptedDetectionForLostAfterNs_ThenSearching) {
  TrackerParams p;
  p.lost_after_frames = 1000;
  p.lost_after_ns = 400'000'000;
  Script s(p);
  s.start_following({0, 0, 2}, kRed);
  EXPECT_EQ(s.step(Detection{}, 300'000'000).state, TrackState::kFollowing);
  EXPECT_EQ(s.step(Detection{}, 100'000'000).state, TrackState::kSearching);
}

// A cut link or a stalled detector delivers nothing for a while: no evidence that the ball is
// gone. Given following, when detections resume after 2 s of silence with the ball looking
// different (block matching fails), then the tracker does not declare a loss at the first
// rejection but re-acquires from the statistics, never searching in between.
TEST(Tracker, GivenFollowing_WhenInputResumesAfterAGap_ThenReacquiredWithoutSearching) {
  Script s;
  s.start_following({0.2, 0.0, 2.0}, kRed);
  const Patch new_look = ball_patch(150, 30, 20, 0.8, 10);
  Eigen::Vector3d ball(0.25, 0.0, 2.0);
  Track t = s.step(detection_at(ball, new_look), 2'000'000'000);
  EXPECT_EQ(t.state, TrackState::kFollowing) << t.reason;
  EXPECT_EQ(t.verdict, Verdict::kRejected) << t.reason;
  for (int frame = 2; frame <= 10 && t.verdict != Verdict::kStatisticsAccepted; ++frame) {
    t = s.see(ball, new_look);
    EXPECT_EQ(t.state, TrackState::kFollowing) << "frame " << frame << ": " << t.reason;
  }
  EXPECT_EQ(t.verdict, Verdict::kStatisticsAccepted) << t.reason;
}

// Given following, when input resumes after a gap without the ball, then the loss is counted
// from the resumption: searching after lost_after_frames detections, as after any loss.
TEST(Tracker, GivenFollowing_WhenInputResumesAfterAGapWithoutTheBall_ThenLossCountedFromThere) {
  TrackerParams p;
  Script s(p);
  s.start_following({0.2, 0.0, 2.0}, kRed);
  EXPECT_EQ(s.step(Detection{}, 2'000'000'000).state, TrackState::kFollowing);
  for (int frame = 2; frame < p.lost_after_frames; ++frame) {
    EXPECT_EQ(s.none().state, TrackState::kFollowing) << "frame " << frame;
  }
  EXPECT_EQ(s.none().state, TrackState::kSearching);
}

TEST(Tracker, GivenBallVanishingNearCentreWhileMovingLeft_ThenLastSeenSideFollowsMotion) {
  Script s;
  s.start_following({0.3, 0, 2}, kRed);
  Eigen::Vector3d ball(0.3, 0, 2);
  Track t;
  for (int i = 0; i < 8; ++i) {
    ball.x() -= 1.0 / 30.0;
    t = s.see(ball, kRed);
  }
  // Still right of centre (x > 0) but heading left
  ASSERT_GT(ball.x(), 0.0);
  EXPECT_LT(t.velocity_mps.x(), -0.1);
  EXPECT_EQ(t.last_seen_side, Side::kLeft);
}

TEST(Tracker, GivenMovingBall_ThenVelocityEstimateMatchesTruth) {
  std::mt19937 rng(11);
  Script s;
  const Eigen::Vector3d v(0.5, 0.0, -0.3);
  Eigen::Vector3d ball(-0.5, 0.1, 2.5);
  Track t;
  for (int i = 0; i < 30; ++i) {
    ball += v / 30.0;
    t = s.see(testing::measured(ball, rng), kRed);
  }
  ASSERT_EQ(t.state, TrackState::kFollowing);
  EXPECT_LT((t.velocity_mps - v).norm(), 0.1);
}

TEST(Tracker, GivenOldRegister_WhenDetectionArrivesAfterLongGap_ThenCollectingRestarts) {
  Script s;
  for (int i = 0; i < 4; ++i) s.see({0, 0, 2}, kRed);
  ASSERT_EQ(s.tracker().position_register().size(), 4);
  const Track t = s.step(detection_at({0, 0, 2}, kRed), 2'000'000'000);
  EXPECT_EQ(t.verdict, Verdict::kStartupCollecting);
  EXPECT_EQ(s.tracker().position_register().size(), 1);
}

// Frames a ball reappearing after a loss long enough to empty the register needs before it
// is accepted again (it rolls on, with a look block matching cannot recognise).
int frames_to_reacquire_after_long_loss(const TrackerParams& p) {
  Script s(p);
  if (s.start_following({0.2, 0.0, 2.0}, kRed).state != TrackState::kFollowing) return -1;
  for (int i = 0; i < 45; ++i) s.none();  // 1.5 s without any detection: register expired
  if (s.none().state != TrackState::kSearching) return -1;
  const Patch new_look = ball_patch(150, 30, 20, 0.8, 10);
  Eigen::Vector3d ball(-0.8, 0.05, 1.6);
  for (int frame = 1; frame <= 10; ++frame) {
    ball.x() += 0.5 / 30.0;
    const Track t = s.see(ball, new_look);
    if (t.state == TrackState::kFollowing) {
      EXPECT_EQ(t.verdict, Verdict::kStatisticsAccepted);
      return frame;
    }
    EXPECT_NE(t.reason.find("register"), std::string::npos) << t.reason;
  }
  return -1;
}

// Given the paper's rule (the full register of five must vouch), a ball reappearing after a
// long loss is accepted at its sixth detection; with reacquire_positions = 3 at its fourth.
// Start-up still needs all five.
TEST(Tracker, GivenReacquirePositions_ThenAReappearingBallIsJudgedFromThatMany) {
  TrackerParams paper;
  paper.reacquire_positions = paper.register_size;
  EXPECT_EQ(frames_to_reacquire_after_long_loss(paper), 6);
  TrackerParams three;
  three.reacquire_positions = 3;
  EXPECT_EQ(frames_to_reacquire_after_long_loss(three), 4);
  Script s(three);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(s.see({0, 0, 2}, kRed).state, TrackState::kIdle);
  EXPECT_EQ(s.see({0, 0, 2}, kRed).state, TrackState::kFollowing);
}

// Given a register refilling with three positions that do not agree (clutter), then nothing is
// accepted: fewer positions, the same tests.
TEST(Tracker, GivenAFewInconsistentPositionsAfterALoss_ThenNothingIsReacquired) {
  Script s;
  s.start_following({0.2, 0.0, 2.0}, kRed);
  for (int i = 0; i < 46; ++i) s.none();
  std::mt19937 rng(21);
  for (int i = 0; i < 30; ++i) {
    const Track t = s.see(testing::clutter_position(rng), testing::clutter_patch(rng));
    EXPECT_NE(t.state, TrackState::kFollowing) << "frame " << i << ": " << t.reason;
  }
}

TEST(Tracker, GivenRejectedDetections_ThenTheyAreStillShiftedIn) {
  Script s;
  s.start_following({0, 0, 2}, kRed);
  const Eigen::Vector3d far(0.6, 0.0, 2.0);
  const Track t = s.see(far, ball_patch(30, 200, 30));
  ASSERT_EQ(t.verdict, Verdict::kRejected);
  EXPECT_NEAR((s.tracker().position_register().entries().back().position_m - far).norm(), 0.0,
              1e-12);
}

TEST(Tracker, GivenFollowing_WhenReset_ThenIdleAgain) {
  Script s;
  s.start_following({0, 0, 2}, kRed);
  s.tracker().reset();
  EXPECT_EQ(s.tracker().state(), TrackState::kIdle);
  EXPECT_FALSE(s.tracker().has_reference_block());
  EXPECT_EQ(s.tracker().position_register().size(), 0);
}

TEST(TrackerNames, GivenEnums_ThenStableNames) {
  EXPECT_EQ(to_string(TrackState::kSearching), "searching");
  EXPECT_EQ(to_string(Side::kLeft), "left");
  EXPECT_EQ(to_string(Verdict::kStatisticsAccepted), "statistics_accepted");
  EXPECT_TRUE(is_accepted(Verdict::kStartupAccepted));
  EXPECT_FALSE(is_accepted(Verdict::kStartupInconsistent));
}

}  // namespace
}  // namespace stereoball::tracker
