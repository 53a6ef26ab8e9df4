// Unit tests of the acceptance criteria on synthetic runs (robot at the origin facing +x,
// 30 frames per second).

#include "acceptance.hpp"
#include "report.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace stereoball::bench_closed_loop {
namespace {

constexpr double kDt = 1.0 / 30.0;

// A frame at index i with the ball at world (x, y), visible or not.
Sample frame(int i, double x, double y, bool visible) {
  Sample s;
  s.truth.seq = static_cast<uint64_t>(i);
  s.truth.t_s = i * kDt;
  s.truth.ball_present = true;
  s.truth.visible = visible;
  s.truth.ball_world_m[0] = x;
  s.truth.ball_world_m[1] = y;
  // camera frame: x right = -world y, z forward = world x (the camera offset does not matter)
  s.truth.ball_cam_m[0] = -y;
  s.truth.ball_cam_m[2] = x;
  s.track.seq = s.truth.seq;
  return s;
}

// The tracker following and accepting the true ball at this frame.
void follow(Sample& s) {
  s.track.state = demo::TrackState::kFollowing;
  s.track.accepted = true;
  for (int k = 0; k < 3; ++k) s.track.position_m[k] = s.truth.ball_cam_m[k];
}

TEST(KeepFigures, GivenStillBallAtTarget_ThenReachableAfterSettlingAndAllKept) {
  // Given a ball 1 m straight ahead, visible for 3 s, followed throughout
  std::vector<Sample> run;
  for (int i = 0; i < 90; ++i) {
    run.push_back(frame(i, 1.0, 0.0, true));
    follow(run.back());
  }
  const KeepFigures k = keep_figures(run, {});
  // Then only the last second (after the 2 s settling time) is reachable, all of it kept
  EXPECT_EQ(k.reachable_frames, 30u);
  EXPECT_NEAR(k.reachable_s, 1.0, 1e-9);
  EXPECT_NEAR(k.kept_s, k.reachable_s, 1e-9);
  EXPECT_NEAR(k.following_s, k.reachable_s, 1e-9);
  EXPECT_NEAR(k.visible_s, 3.0, 1e-9);
}

TEST(KeepFigures, GivenBallTooFarAndOffCentre_ThenNotKeptAndTheCauseIsSeparated) {
  // Given a ball 1.5 m ahead (0.5 m too far) but centred, for 3 s
  std::vector<Sample> far;
  for (int i = 0; i < 90; ++i) far.push_back(frame(i, 1.5, 0.0, true));
  const KeepFigures k = keep_figures(far, {});
  // Then none of the reachable time is kept: the distance fails, the bearing is fine
  EXPECT_GT(k.reachable_s, 0.0);
  EXPECT_EQ(k.kept_s, 0.0);
  EXPECT_EQ(k.distance_ok_s, 0.0);
  EXPECT_NEAR(k.bearing_ok_s, k.reachable_s, 1e-9);
  EXPECT_NEAR(k.distance_error_sum_m / k.reachable_frames, 0.5, 1e-9);
  // Given a ball at 1 m but 10 degrees to the side, Then the bearing fails
  std::vector<Sample> side;
  const double a = 10.0 * M_PI / 180;
  for (int i = 0; i < 90; ++i) side.push_back(frame(i, std::cos(a), std::sin(a), true));
  const KeepFigures s = keep_figures(side, {});
  EXPECT_EQ(s.kept_s, 0.0);
  EXPECT_NEAR(s.distance_ok_s, s.reachable_s, 1e-9);
  EXPECT_EQ(s.bearing_ok_s, 0.0);
}

TEST(KeepFigures, GivenBallFasterThanTheRobot_ThenNotReachableUntilSlowForTheSettlingTime) {
  // Given a ball at 1 m, 1.0 m/s fast for 1 s, then still for 2.5 s
  std::vector<Sample> run;
  for (int i = 0; i < 105; ++i) {
    run.push_back(frame(i, 1.0, 0.0, true));
    run.back().ball_speed_mps = i < 30 ? 1.0 : 0.0;
  }
  AcceptanceParams p;
  p.max_ball_speed_mps = 0.8;
  const KeepFigures k = keep_figures(run, p);
  // Then the fast second is counted as too fast and reachable time starts 2 s after it
  EXPECT_NEAR(k.fast_s, 1.0, 1e-9);
  EXPECT_EQ(k.reachable_frames, 15u);
}

// Ball visible on one side for 1 s, out of view for gap_frames, then back in view; the
// controller searches with search_radps from 1.2 s; the tracker follows it again from
// frame reacquire_frame (-1: never).
std::vector<Sample> leave_run(double side_y, int gap_frames, double search_radps,
                              int reacquire_frame, int frames = 150) {
  std::vector<Sample> run;
  for (int i = 0; i < frames; ++i) {
    const bool visible = i < 30 || i >= 30 + gap_frames;
    run.push_back(frame(i, 1.0, side_y, visible));
    if (i < 30 || (reacquire_frame >= 0 && i >= reacquire_frame)) follow(run.back());
    if (i >= 36 && (reacquire_frame < 0 || i < reacquire_frame)) {
      run.back().track.state = demo::TrackState::kSearching;
      run.back().searching = true;
      run.back().angular_radps = search_radps;
    }
  }
  return run;
}

TEST(LeaveEvents, GivenBallLeavesRightAndRobotSearchesRight_ThenRightWayAndReacquired) {
  // Given the ball leaving to the right (world y < 0), a clockwise search, reacquired at 2.2 s
  const auto events = leave_events(leave_run(-0.3, 30, -0.8, 66), {});
  // Then one event: side right, turned right, reacquired 1.2 s after leaving
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].side, Side::kRight);
  EXPECT_EQ(events[0].turned, Side::kRight);
  EXPECT_TRUE(events[0].right_way);
  EXPECT_TRUE(events[0].reacquired);
  EXPECT_NEAR(events[0].reacquire_s, 1.2, 1e-9);
  EXPECT_TRUE(leave_run_ok(events));
  EXPECT_EQ(judged_leaves(events), 1u);
}

TEST(LeaveEvents, GivenBallLeavesLeftButRobotTurnsRight_ThenWrongWayAndTheRunFails) {
  // Given the ball leaving to the left (world y > 0) and a clockwise (right) search
  const auto events = leave_events(leave_run(0.3, 30, -0.8, 66), {});
  ASSERT_EQ(events.size(), 1u);
  // Then the event is judged the wrong way even though the ball was reacquired
  EXPECT_EQ(events[0].side, Side::kLeft);
  EXPECT_EQ(events[0].turned, Side::kRight);
  EXPECT_FALSE(events[0].right_way);
  EXPECT_FALSE(leave_run_ok(events));
}

TEST(LeaveEvents, GivenNoReacquisitionWithinTheLimit_ThenTheRunFails) {
  // Given a right turn but the tracker never follows again, over a 12 s run
  AcceptanceParams p;
  p.reacquire_limit_s = 5.0;
  const auto events = leave_events(leave_run(-0.3, 30, -0.8, -1, 360), p);
  ASSERT_EQ(events.size(), 1u);
  // Then not reacquired, judged (the run outlasted the limit), failing
  EXPECT_FALSE(events[0].reacquired);
  EXPECT_FALSE(events[0].cut_off);
  EXPECT_FALSE(leave_run_ok(events));
}

TEST(LeaveEvents, GivenRunEndsBeforeTheLimit_ThenTheEventIsNotJudged) {
  // Given the ball out of view until the end of a 2 s run, never reacquired
  const auto events = leave_events(leave_run(-0.3, 100, -0.8, -1, 60), {});
  ASSERT_EQ(events.size(), 1u);
  // Then the event is cut off, not judged, and does not fail the run
  EXPECT_TRUE(events[0].cut_off);
  EXPECT_EQ(judged_leaves(events), 0u);
  EXPECT_TRUE(leave_run_ok(events));
}

TEST(LeaveEvents, GivenShortDropout_ThenNoLeaveEvent) {
  // Given the ball out of view for 0.2 s only (< 0.5 s)
  const auto events = leave_events(leave_run(-0.3, 6, -0.8, 36), {});
  // Then it did not "leave the view"
  EXPECT_TRUE(events.empty());
}

TEST(LeaveEvents, GivenTrackFollowingClutterWhenBallIsBack_ThenNotReacquired) {
  // Given the track following a position 1 m away from the true ball after it came back
  auto run = leave_run(-0.3, 30, -0.8, 66, 360);
  for (auto& s : run)
    if (s.truth.t_s >= 2.2) s.track.position_m[2] += 1.0;
  AcceptanceParams p;
  p.reacquire_limit_s = 5.0;
  const auto events = leave_events(run, p);
  ASSERT_EQ(events.size(), 1u);
  // Then following clutter is not reacquiring the ball
  EXPECT_FALSE(events[0].reacquired);
}

TEST(JudgeRun, GivenNoBallAndFollowingForOneSecond_ThenLongestFollowingIsMeasured) {
  // Given no ball and the track 'following' clutter from 1.0 s to the end of a 2 s run
  std::vector<Sample> run;
  for (int i = 0; i < 60; ++i) {
    run.push_back(frame(i, 0, 0, false));
    run.back().truth.ball_present = false;
    if (i >= 30) run.back().track.state = demo::TrackState::kFollowing;
  }
  const RunAcceptance r = judge_run("no_ball", run, {});
  // Then (c) sees about one second of following (first to last frame) and no (a)/(b) data
  EXPECT_FALSE(r.ball_present);
  EXPECT_NEAR(r.longest_following_no_ball_s, 29 * kDt, 1e-9);
  EXPECT_EQ(r.keep.reachable_s, 0.0);
  EXPECT_TRUE(r.leaves.empty());
}

TEST(Summary, GivenEventsCutOffByTheRunsEnd_ThenTheirSearchTurnsAreCountedApartFromTheJudged) {
  // Given one run with a judged event and three cut off by the run's end: one searched toward
  // the side the ball left on, one the other way, one never searched
  JudgedRun run;
  run.result.ball_present = true;
  LeaveEvent judged;
  judged.side = judged.turned = Side::kLeft;
  judged.right_way = judged.reacquired = true;
  LeaveEvent toward, away, no_search;
  toward.cut_off = away.cut_off = no_search.cut_off = true;
  toward.side = toward.turned = Side::kRight;
  away.side = Side::kLeft;
  away.turned = Side::kRight;
  no_search.side = Side::kRight;
  run.result.leaves = {judged, toward, away, no_search};
  const Summary s = summarize("all", {&run}, {});
  // Then (b) judges only the first; the cut-off ones count apart: 2 searched, 1 the right way
  EXPECT_EQ(s.leave_events, 1);
  EXPECT_EQ(s.leave_ok_runs, 1);
  EXPECT_EQ(s.cut_off_events, 3);
  EXPECT_EQ(s.cut_off_searched, 2);
  EXPECT_EQ(s.cut_off_right_way, 1);
  // And the verdict line and the JSON say so
  char* text = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&text, &size);
  ASSERT_NE(out, nullptr);
  print_report(out, {s}, s, {});
  std::fclose(out);
  const std::string report(text, size);
  std::free(text);
  EXPECT_NE(report.find("3 event(s) cut off by the run's end; of those, 2 searched: 1 toward the "
                        "side the ball left on"),
            std::string::npos)
      << report;
  const nlohmann::json j = to_json({}, {s}, s, {});
  EXPECT_EQ(j["total"]["b"]["cut_off_searched"], 2);
  EXPECT_EQ(j["total"]["b"]["cut_off_right_way"], 1);
}

TEST(Trace, GivenSamples_ThenOneCsvLinePerFrameWithTheCommandInForce) {
  // Given two frames, the second answered by a search command turning right and backing off
  std::vector<Sample> run = {frame(0, 1.0, 0.0, true), frame(1, 1.0, 0.0, false)};
  run[1].searching = true;
  run[1].angular_radps = -0.8;
  run[1].linear_mps = -0.1;
  char* text = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&text, &size);
  ASSERT_NE(out, nullptr);
  write_trace(out, run);
  std::fclose(out);
  const std::string csv(text, size);
  std::free(text);
  // Then a header naming both command columns and the command in the last frame's line
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "t_s,ball_present,visible,ball_speed_mps,distance_m,bearing_deg,detected,track_state,"
            "accepted,track_x_m,track_z_m,searching,angular_radps,linear_mps");
  EXPECT_NE(csv.find("0.0333,1,0,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",1,-0.8000,-0.1000\n"), std::string::npos) << csv;
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3);
}

}  // namespace
}  // namespace stereoball::bench_closed_loop
