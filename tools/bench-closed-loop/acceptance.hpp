#pragma once
// The closed-loop acceptance criteria of issue 7, judged on the frames of one run against the
// simulator's ground truth. Pure: the benchmark feeds it samples converted from the loop.

#include <cstdint>
#include <string>
#include <vector>

#include "metrics.hpp"

namespace stereoball::bench_closed_loop {

/// One camera frame of a run, as the criteria see it.
struct Sample {
  demo::TruthSample truth;          ///< ground truth (time, visibility, world poses)
  double ball_speed_mps = 0.0;      ///< true ball speed over the floor, m/s
  demo::DetectionSample detection;  ///< the detector's output (camera frame)
  demo::TrackSample track;          ///< tracker state, acceptance, position (camera frame)
  bool searching = false;           ///< the controller command in force is in searching mode
  double angular_radps = 0.0;       ///< that command's yaw rate, rad/s, positive = turn left
  double linear_mps = 0.0;          ///< that command's forward speed, m/s
};

/// Thresholds of the criteria; defaults are the figures and the shipped controller.
struct AcceptanceParams {
  double target_distance_m = 1.0;  ///< the controller's target distance (robot centre), m
  double distance_tolerance_m = 0.25;
  double bearing_tolerance_rad = 5.0 * 3.14159265358979323846 / 180.0;
  double max_ball_speed_mps = 0.8;  ///< faster balls are unreachable (controller max_linear_mps)
  double settle_s = 2.0;            ///< reachable only after the conditions held this long, s
  double min_gap_s = 0.5;  ///< the ball "left the view" if out of view at least this long, s
  double reacquire_limit_s = 10.0;  ///< reacquired = following the ball again within this, s
  /// A searching command turning at least this fast shows the search direction, rad/s (half
  /// the controller's search speed: the first ramping commands may still carry the old turn).
  double search_turn_radps = 0.4;
  double on_ball_m = 0.3;  ///< an accepted track position this close to the truth is the ball
  double max_following_no_ball_s = 0.5;  ///< (c): longest allowed following with no ball, s
  double frame_period_s = 1.0 / 30.0;    ///< time one frame stands for, s
};

/// (a) Time the ball was reachable and how it was kept, seconds.
struct KeepFigures {
  double visible_s = 0.0;    ///< ball visible in both eyes
  double fast_s = 0.0;       ///< visible, but faster than max_ball_speed_mps
  double reachable_s = 0.0;  ///< the denominator of (a)
  double kept_s = 0.0;       ///< reachable and within both tolerances
  double distance_ok_s = 0.0;
  double bearing_ok_s = 0.0;
  double following_s = 0.0;           ///< reachable and the track following
  double distance_error_sum_m = 0.0;  ///< sum over reachable frames of (distance - target)
  double abs_bearing_sum_rad = 0.0;   ///< sum over reachable frames of |bearing|
  std::size_t reachable_frames = 0;
};

/// Side of the robot's heading.
enum class Side { kNone, kLeft, kRight };

/// (b) One time the ball left the view.
struct LeaveEvent {
  double t_s = 0.0;           ///< first frame the ball was out of view, s
  Side side = Side::kNone;    ///< where it left (bearing at the last visible frame)
  Side turned = Side::kNone;  ///< direction of the first searching rotation (none: no search)
  bool right_way = false;     ///< turned toward side (or reacquired without searching)
  bool reacquired = false;    ///< following the ball again within reacquire_limit_s
  double reacquire_s = -1.0;  ///< time from leaving to following the ball again (-1: never)
  bool cut_off = false;       ///< run ended before the limit without reacquisition: not judged
};

/// Everything judged on one run.
struct RunAcceptance {
  bool ball_present = false;
  KeepFigures keep;
  std::vector<LeaveEvent> leaves;
  double longest_following_no_ball_s = 0.0;  ///< (c), from demo::score
  demo::ScenarioMetrics metrics;             ///< the demo's figures for the same run
};

/// Judges one run (samples in time order).
RunAcceptance judge_run(const std::string& scenario, const std::vector<Sample>& samples,
                        const AcceptanceParams& params);

/// (a) alone.
KeepFigures keep_figures(const std::vector<Sample>& samples, const AcceptanceParams& params);
/// (b) alone.
std::vector<LeaveEvent> leave_events(const std::vector<Sample>& samples,
                                     const AcceptanceParams& params);
/// A run passes (b) if every judged leave event turned the right way and was reacquired.
bool leave_run_ok(const std::vector<LeaveEvent>& events);
/// Leave events that are judged (not cut off by the end of the run).
std::size_t judged_leaves(const std::vector<LeaveEvent>& events);

/// "left" / "right" / "none".
const char* to_string(Side side);

}  // namespace stereoball::bench_closed_loop
