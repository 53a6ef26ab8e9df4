// Statistical behaviour of the tracker on long synthetic sequences: false
// detections on clutter must almost never be accepted, a visible ball almost
// always. The figures are printed so a regression shows how far it moved.

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "tracker/core/tracker.hpp"
#include "tracker/core/tracker_test_support.hpp"

namespace stereoball::tracker {
namespace {

using testing::kFramePeriodNs;

struct Rates {
  int frames = 0;
  int accepted = 0;
  double fraction() const { return frames ? static_cast<double>(accepted) / frames : 0.0; }
};

// A smooth ball path in front of the camera (speeds up to ~0.4 m/s).
Eigen::Vector3d ball_path(double t_s) {
  return {0.6 * std::sin(0.5 * t_s), 0.15, 2.0 + 0.6 * std::cos(0.3 * t_s)};
}

Detection clutter_detection(std::mt19937& rng) {
  return testing::detection_at(testing::clutter_position(rng), testing::clutter_patch(rng));
}

TEST(TrackerClutter, GivenNoBall_WhenDetectorReportsClutterEveryFrame_ThenBelowOnePercentAccepted) {
  Rates rates;
  for (unsigned seed = 1; seed <= 3; ++seed) {
    std::mt19937 rng(seed);
    Tracker tracker{TrackerParams{}};
    std::int64_t now = 0;
    for (int i = 0; i < 20'000; ++i) {
      now += kFramePeriodNs;
      const Track t = tracker.step(clutter_detection(rng), now);
      ++rates.frames;
      rates.accepted += is_accepted(t.verdict) ? 1 : 0;
    }
  }
  std::printf("clutter every frame: %d of %d false detections accepted (%.4f%%)\n", rates.accepted,
              rates.frames, 100.0 * rates.fraction());
  EXPECT_LT(rates.fraction(), 0.01);
}

TEST(TrackerClutter, GivenNoBall_WhenClutterIsIntermittent_ThenBelowOnePercentAccepted) {
  Rates rates;
  std::mt19937 rng(21);
  std::bernoulli_distribution present(0.3);
  Tracker tracker{TrackerParams{}};
  std::int64_t now = 0;
  for (int i = 0; i < 60'000; ++i) {
    now += kFramePeriodNs;
    if (!present(rng)) {
      tracker.step(Detection{}, now);
      continue;
    }
    const Track t = tracker.step(clutter_detection(rng), now);
    ++rates.frames;
    rates.accepted += is_accepted(t.verdict) ? 1 : 0;
    ASSERT_NE(t.state, TrackState::kSearching);  // it never followed anything
  }
  std::printf("intermittent clutter: %d of %d accepted (%.4f%%)\n", rates.accepted, rates.frames,
              100.0 * rates.fraction());
  EXPECT_LT(rates.fraction(), 0.01);
}

// A visible ball with measurement noise, pixel noise and lighting drift in its
// block, plus detector outliers (clutter picked instead of the ball) and misses.
struct VisibleBallRun {
  Rates ball;
  Rates outliers;
};

VisibleBallRun run_visible_ball(unsigned seed, int block_noise, double outlier_rate) {
  std::mt19937 rng(seed);
  std::bernoulli_distribution outlier(outlier_rate);
  std::bernoulli_distribution miss(0.02);
  Tracker tracker{TrackerParams{}};
  VisibleBallRun run;
  std::int64_t now = 0;
  for (int i = 0; i < 9'000; ++i) {  // five minutes at 30 fps
    now += kFramePeriodNs;
    const double t_s = i / 30.0;
    if (miss(rng)) {
      tracker.step(Detection{}, now);
      continue;
    }
    const bool is_outlier = i > 30 && outlier(rng);
    const Detection d =
        is_outlier ? clutter_detection(rng)
                   : testing::detection_at(
                         testing::measured(ball_path(t_s), rng),
                         testing::noisy(testing::ball_patch(220, 50, 40, 0.9 + 0.1 * std::sin(t_s)),
                                        rng, block_noise));
    const Track t = tracker.step(d, now);
    if (i < 30) continue;  // the start-up second is not counted
    Rates& r = is_outlier ? run.outliers : run.ball;
    ++r.frames;
    r.accepted += is_accepted(t.verdict) ? 1 : 0;
  }
  return run;
}

TEST(TrackerClutter, GivenVisibleBallWithOutliers_ThenBallAcceptedAndOutliersRejected) {
  Rates ball;
  Rates outliers;
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const auto run = run_visible_ball(seed, 8, 0.03);
    ball.frames += run.ball.frames;
    ball.accepted += run.ball.accepted;
    outliers.frames += run.outliers.frames;
    outliers.accepted += run.outliers.accepted;
  }
  std::printf("visible ball: %.2f%% of ball frames accepted, %.2f%% of %d outliers accepted\n",
              100.0 * ball.fraction(), 100.0 * outliers.fraction(), outliers.frames);
  EXPECT_GE(ball.fraction(), 0.98);
  EXPECT_LT(outliers.fraction(), 0.01);
}

TEST(TrackerClutter, GivenVisibleBallWhoseBlockNeverMatches_ThenStatisticsStillAccept) {
  // Given pixel noise so strong (+-40 per byte) that the SSD is always above 200,000
  const auto run = run_visible_ball(5, 40, 0.0);
  std::printf("block matching disabled by noise: %.2f%% of ball frames accepted\n",
              100.0 * run.ball.fraction());
  // Then the line / mean tests alone keep the ball
  EXPECT_GE(run.ball.fraction(), 0.95);
}

TEST(TrackerClutter, GivenBlockNeverMatchesAndOutliers_ThenStraysDoNotStallStatistics) {
  // Given no block matching and 3% clutter outliers: each outlier spoils the
  // register for five frames unless a single stray position may be left out
  Rates ball;
  Rates outliers;
  for (unsigned seed = 1; seed <= 2; ++seed) {
    const auto run = run_visible_ball(seed, 40, 0.03);
    ball.frames += run.ball.frames;
    ball.accepted += run.ball.accepted;
    outliers.frames += run.outliers.frames;
    outliers.accepted += run.outliers.accepted;
  }
  std::printf("no block match, 3%% outliers: %.2f%% of ball frames, %.2f%% of outliers accepted\n",
              100.0 * ball.fraction(), 100.0 * outliers.fraction());
  EXPECT_GE(ball.fraction(), 0.98);
  EXPECT_LT(outliers.fraction(), 0.01);
}

TEST(TrackerClutter, GivenFollowedBallLeaves_WhenOnlyClutterFollows_ThenClutterRejected) {
  Rates rates;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    std::mt19937 rng(seed);
    Tracker tracker{TrackerParams{}};
    std::int64_t now = 0;
    for (int i = 0; i < 60; ++i) {
      now += kFramePeriodNs;
      tracker.step(testing::detection_at(testing::measured(ball_path(i / 30.0), rng),
                                         testing::ball_patch(220, 50, 40)),
                   now);
    }
    EXPECT_EQ(tracker.state(), TrackState::kFollowing);
    for (int i = 0; i < 1'000; ++i) {
      now += kFramePeriodNs;
      const Track t = tracker.step(clutter_detection(rng), now);
      ++rates.frames;
      rates.accepted += is_accepted(t.verdict) ? 1 : 0;
    }
    EXPECT_EQ(tracker.state(), TrackState::kSearching);
  }
  std::printf("clutter after loss: %d of %d accepted\n", rates.accepted, rates.frames);
  EXPECT_LT(rates.fraction(), 0.01);
}

}  // namespace
}  // namespace stereoball::tracker
