#include "metrics.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

namespace stereoball::demo {
namespace {

TruthSample truth(uint64_t seq, double t, bool visible, double z = 1.0, double x = 0.0) {
  TruthSample s;
  s.seq = seq;
  s.t_s = t;
  s.ball_present = true;
  s.visible = visible;
  s.ball_cam_m[0] = x;
  s.ball_cam_m[2] = z;
  // Robot at the origin facing +x (world y = left): the same ball seen from the world.
  s.ball_world_m[0] = z;
  s.ball_world_m[1] = -x;
  return s;
}

TrackSample track(uint64_t seq, TrackState state, bool accepted, double z, double x = 0.0) {
  TrackSample s;
  s.seq = seq;
  s.state = state;
  s.accepted = accepted;
  s.position_m[0] = x;
  s.position_m[2] = z;
  return s;
}

DetectionSample detection(uint64_t seq, bool found, double z, double x = 0.0) {
  DetectionSample d;
  d.seq = seq;
  d.found = found;
  d.position_m[0] = x;
  d.position_m[2] = z;
  return d;
}

// One scenario's samples, a frame at a time.
struct Samples {
  std::vector<TruthSample> gt;
  std::vector<DetectionSample> det;
  std::vector<TrackSample> trk;
  void add(const TruthSample& g, const DetectionSample& d, const TrackSample& t) {
    gt.push_back(g);
    det.push_back(d);
    trk.push_back(t);
  }
  ScenarioMetrics scored(const std::string& name) const { return score(name, gt, det, trk, {}); }
};

TEST(Metrics, GivenAccurateTrackWhenScoredThenErrorsAndRatesMatch) {
  Samples run;
  for (uint64_t i = 0; i < 10; ++i)
    run.add(truth(i, i * 0.1, true, 1.0), detection(i, i % 2 == 0, 1.01),
            track(i, TrackState::kFollowing, true, 1.02));
  const auto m = run.scored("s");
  EXPECT_EQ(m.frames, 10u);
  EXPECT_EQ(m.visible_frames, 10u);
  EXPECT_DOUBLE_EQ(m.detection_rate, 0.5);
  EXPECT_NEAR(m.error_median_m, 0.02, 1e-9);
  EXPECT_NEAR(m.error_median_rel, 0.02, 1e-9);
  EXPECT_DOUBLE_EQ(m.accept_rate_visible, 1.0);
  EXPECT_NEAR(m.following_distance_error_m, 0.0, 1e-12);  // target 1 m, ball at 1 m
  EXPECT_DOUBLE_EQ(m.within_tolerance, 1.0);
}

TEST(Metrics, GivenDetectionsOnClutterThenFalseAcceptRateCountsOnlyAcceptedOnes) {
  Samples run;
  for (uint64_t i = 0; i < 4; ++i)
    run.add(truth(i, i * 0.1, false), detection(i, true, 3.0),
            track(i, TrackState::kIdle, i == 3, 3.0));
  const auto m = run.scored("clutter");
  EXPECT_EQ(m.false_detections, 4u);
  EXPECT_DOUBLE_EQ(m.false_accept_rate, 0.25);
}

TEST(Metrics, GivenBallLostThenReacquireTimeIsFromVisibilityToFirstAcceptance) {
  std::vector<TruthSample> gt;
  std::vector<TrackSample> trk;
  // visible 0..0.9 s, invisible 1.0..1.9 s, visible again from 2.0 s, accepted from 2.3 s
  for (uint64_t i = 0; i < 30; ++i) {
    const double t = i * 0.1;
    const bool visible = t < 0.95 || t > 1.95;
    gt.push_back(truth(i, t, visible));
    const bool acc = t < 0.95 || t > 2.25;
    trk.push_back(track(i, acc ? TrackState::kFollowing : TrackState::kSearching, acc, 1.0));
  }
  const auto m = score("loss", gt, {}, trk, {});
  EXPECT_EQ(m.losses, 1u);
  EXPECT_EQ(m.reacquired, 1u);
  EXPECT_NEAR(m.reacquire_median_s, 0.3, 1e-9);
}

TEST(Metrics, GivenFollowingWithoutBallThenLongestBlindFollowingIsMeasured) {
  std::vector<TruthSample> gt;
  std::vector<TrackSample> trk;
  for (uint64_t i = 0; i < 10; ++i) {
    gt.push_back(truth(i, i * 0.1, false));
    trk.push_back(track(i, i >= 4 ? TrackState::kFollowing : TrackState::kIdle, false, 2.0));
  }
  const auto m = score("blind", gt, {}, trk, {});
  EXPECT_NEAR(m.longest_following_without_ball_s, 0.5, 1e-9);
}

TEST(Metrics, GivenBallOffCentreThenItIsOutsideTolerance) {
  std::vector<TruthSample> gt{truth(0, 0, true, 1.0, 0.2)};  // ~11 degrees off centre
  std::vector<TrackSample> trk{track(0, TrackState::kFollowing, true, 1.0, 0.2)};
  const auto m = score("off", gt, {}, trk, {});
  EXPECT_DOUBLE_EQ(m.within_tolerance, 0.0);
}

TEST(Metrics, GivenRobotTurnedAndMoved_ThenDistanceAndBearingFromItsCentre) {
  // Given the robot at (1, 1) facing +y (yaw 90 deg) and the ball at (2, 3): 2 m ahead, 1 m right
  TruthSample t;
  t.robot_world_m[0] = 1.0;
  t.robot_world_m[1] = 1.0;
  t.robot_yaw_rad = M_PI / 2;
  t.ball_world_m[0] = 2.0;
  t.ball_world_m[1] = 3.0;
  // Then the distance is from the robot centre and the bearing is positive (right)
  EXPECT_NEAR(robot_ball_distance_m(t), std::sqrt(5.0), 1e-12);
  EXPECT_NEAR(robot_ball_bearing_rad(t), std::atan2(1.0, 2.0), 1e-12);
  // And a ball to the left behind the robot gets a negative bearing near -180 deg, not +180+
  t.ball_world_m[0] = 0.9;
  t.ball_world_m[1] = 0.0;
  EXPECT_LT(robot_ball_bearing_rad(t), -M_PI / 2);
  EXPECT_GT(robot_ball_bearing_rad(t), -M_PI);
}

TEST(Metrics, GivenBallAtTargetFromCameraButNotFromRobotCentre_ThenOutsideTolerance) {
  // Given the ball 1.0 m from the camera but the robot centre 0.3 m further back (1.3 m)
  TruthSample gt = truth(0, 0, true, 1.0);
  gt.robot_world_m[0] = -0.3;
  std::vector<TrackSample> trk{track(0, TrackState::kFollowing, true, 1.0)};
  // Then the distance error counts from the robot centre and the frame is out of tolerance
  const auto m = score("offset", {gt}, {}, trk, {});
  EXPECT_NEAR(m.following_distance_error_m, 0.3, 1e-9);
  EXPECT_DOUBLE_EQ(m.within_tolerance, 0.0);
}

// A hand-made run for leave events, 10 frames per second: the ball visible (at camera x) up to
// frame lost_at, the track state of each frame from a string (F following, S searching,
// I idle), and the robot's yaw turning at yaw_rate_of(i) rad per frame.
struct LeaveRun {
  std::vector<TruthSample> gt;
  std::vector<TrackSample> trk;
  LeaveRun(const std::string& states, size_t lost_at, double ball_x,
           const std::function<double(size_t)>& yaw_step) {
    double yaw = 0;
    for (size_t i = 0; i < states.size(); ++i) {
      yaw += yaw_step(i);
      TruthSample g = truth(i, i * 0.1, i < lost_at, 1.0, ball_x);
      g.robot_yaw_rad = std::remainder(yaw, 2.0 * M_PI);
      gt.push_back(g);
      const TrackState s = states[i] == 'F'   ? TrackState::kFollowing
                           : states[i] == 'S' ? TrackState::kSearching
                                              : TrackState::kIdle;
      trk.push_back(track(i, s, s == TrackState::kFollowing, 1.0, ball_x));
    }
  }
};

TEST(LeaveEvents, GivenALeaveToTheRightAndAReturn_ThenOneEventSearchedRightAndReacquired) {
  // Given following for 1 s, the ball last seen right of the axis at frame 9, the track
  // searching from frame 10 to 19 while the robot turns right (clockwise), following from 20
  LeaveRun run(std::string(10, 'F') + std::string(10, 'S') + std::string(10, 'F'), 10, 0.3,
               [](size_t i) { return i >= 10 && i < 20 ? -0.08 : 0.0; });
  // When the events are extracted (samples in reverse order: joined by seq)
  std::reverse(run.gt.begin(), run.gt.end());
  const auto events = leave_events(run.gt, run.trk);
  // Then one leave at 1.0 s by the right, searched right, reacquired at 2.0 s after 1.0 s
  ASSERT_EQ(events.size(), 1u);
  const LeaveEvent& e = events[0];
  EXPECT_EQ(e.seq, 10u);
  EXPECT_NEAR(e.t_s, 1.0, 1e-9);
  EXPECT_EQ(e.ball_side, Side::kRight);
  EXPECT_EQ(e.searched, Side::kRight);
  EXPECT_TRUE(e.searched_ball_side());
  EXPECT_NEAR(e.search_end_t_s, 1.9, 1e-9);
  EXPECT_TRUE(e.reacquired);
  EXPECT_NEAR(e.reacquired_t_s, 2.0, 1e-9);
  EXPECT_NEAR(e.reacquire_s, 1.0, 1e-9);
  EXPECT_STREQ(side_name(e.searched), "right");
}

TEST(LeaveEvents, GivenALeaveWithoutReturn_ThenNotReacquiredAndTheWrongSideIsSeen) {
  // Given the ball lost right of the axis, the track searching to the end of the run, the
  // robot first braking its right turn (0.4 s) then turning left past +-180 deg
  LeaveRun run(std::string(5, 'F') + std::string(40, 'S'), 5, 0.2, [](size_t i) {
    if (i < 5) return -0.1;
    return i < 9 ? -0.05 : 0.12;
  });
  const auto events = leave_events(run.gt, run.trk);
  // Then one leave, by the right, searched left (the braking is not the search), not reacquired,
  // the search ending with the run
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].ball_side, Side::kRight);
  EXPECT_EQ(events[0].searched, Side::kLeft);
  EXPECT_FALSE(events[0].searched_ball_side());
  EXPECT_FALSE(events[0].reacquired);
  EXPECT_EQ(events[0].reacquired_t_s, -1.0);
  EXPECT_EQ(events[0].reacquire_s, -1.0);
  EXPECT_NEAR(events[0].search_end_t_s, 4.4, 1e-9);
}

TEST(LeaveEvents, GivenNoLeave_ThenNoEvents) {
  // Given a run that starts idle and then follows throughout, and one that stays idle
  LeaveRun following(std::string(5, 'I') + std::string(20, 'F'), 25, 0.1,
                     [](size_t) { return 0.01; });
  LeaveRun idle(std::string(20, 'I'), 0, 0.0, [](size_t) { return 0.0; });
  // Then neither has a leave event, and no samples give none either
  EXPECT_TRUE(leave_events(following.gt, following.trk).empty());
  EXPECT_TRUE(leave_events(idle.gt, idle.trk).empty());
  EXPECT_TRUE(leave_events({}, {}).empty());
}

TEST(LeaveEvents, GivenTwoLeavesAndMissingTracks_ThenEachIsJudgedOnItsOwn) {
  // Given a leave by the left searched left and reacquired, then one by the right with a short
  // search (0.2 s) and no turn; tracks missing for frames 12 and 13 (the state carries on)
  LeaveRun run(std::string(5, 'F') + std::string(5, 'S') + std::string(10, 'F') +
                   std::string(2, 'S') + std::string(5, 'F'),
               100, -0.3, [](size_t i) { return i >= 5 && i < 10 ? 0.1 : 0.0; });
  for (size_t i = 0; i < 10; ++i) run.gt[i].ball_cam_m[0] = -0.3;
  for (size_t i = 10; i < run.gt.size(); ++i) run.gt[i].ball_cam_m[0] = 0.3;
  run.trk.erase(run.trk.begin() + 12, run.trk.begin() + 14);
  const auto events = leave_events(run.gt, run.trk);
  // Then two events: the first left/left after 0.5 s, the second right with no search turn
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].ball_side, Side::kLeft);
  EXPECT_EQ(events[0].searched, Side::kLeft);
  EXPECT_NEAR(events[0].reacquire_s, 0.5, 1e-9);
  EXPECT_NEAR(events[1].t_s, 2.0, 1e-9);
  EXPECT_EQ(events[1].ball_side, Side::kRight);
  EXPECT_EQ(events[1].searched, Side::kUnknown);
  EXPECT_FALSE(events[1].searched_ball_side());
  EXPECT_NEAR(events[1].reacquire_s, 0.2, 1e-9);
}

}  // namespace

// Given detections of a ball whose centre is out of one image (entering or leaving the view),
// then they are not false detections; the same detections with no ball in the scene are.
TEST(Metrics, GivenDetectionsOfABallPartlyInViewThenTheyAreNotFalse) {
  Samples run;
  for (uint64_t i = 0; i < 4; ++i)
    run.add(truth(i, i * 0.1, false, 1.0), detection(i, true, 1.0),
            track(i, TrackState::kFollowing, true, 1.0));
  auto m = run.scored("partly in view");
  EXPECT_EQ(m.false_detections, 0u);
  EXPECT_DOUBLE_EQ(m.false_accept_rate, 0.0);
  for (auto& g : run.gt) g.ball_present = false;
  m = run.scored("no ball");
  EXPECT_EQ(m.false_detections, 4u);
  EXPECT_DOUBLE_EQ(m.false_accept_rate, 1.0);
}

}  // namespace stereoball::demo
