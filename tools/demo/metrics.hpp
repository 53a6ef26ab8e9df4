#pragma once
// Scoring of a closed-loop run against the simulator's ground truth. Pure: the demo and the
// closed-loop benchmark feed it samples converted from messages.

#include <cstdint>
#include <string>
#include <vector>

#include "tracker/core/track_state.hpp"

namespace stereoball::demo {

using TrackState = tracker::TrackState;
using Side = tracker::Side;

/// Ground truth of one frame.
struct TruthSample {
  uint64_t seq = 0;
  double t_s = 0;  ///< simulated time, seconds
  bool ball_present = false;
  bool visible = false;              ///< ball centre visible in both eyes
  double ball_cam_m[3] = {0, 0, 0};  ///< left rectified camera frame
  double ball_world_m[2] = {0, 0};
  double robot_world_m[2] = {0, 0};
  double robot_yaw_rad = 0;
};

struct DetectionSample {
  uint64_t seq = 0;
  bool found = false;
  double position_m[3] = {0, 0, 0};
};

struct TrackSample {
  uint64_t seq = 0;
  TrackState state = TrackState::kIdle;
  bool accepted = false;  ///< this frame's detection was accepted
  double position_m[3] = {0, 0, 0};
};

struct MetricsParams {
  double target_distance_m = 1.0;  ///< the controller's target distance
  double distance_tolerance_m = 0.25;
  double bearing_tolerance_rad = 5.0 * 3.14159265358979 / 180.0;
  double false_error_m = 0.3;  ///< an accepted position this far from the truth is false
  double min_gap_s = 0.5;      ///< shorter invisibility is not a "loss"
};

struct ScenarioMetrics {
  std::string scenario;
  size_t frames = 0;
  size_t visible_frames = 0;
  double detection_rate = 0;     ///< found detections / visible frames
  size_t false_detections = 0;   ///< found but not the ball (no ball, or far off it)
  double false_accept_rate = 0;  ///< of false detections, fraction the tracker accepted
  size_t accepted_frames = 0;
  double accept_rate_visible = 0;              ///< visible frames with an accepted track
  double error_median_m = 0, error_p95_m = 0;  ///< accepted vs truth, visible frames
  double error_median_rel = 0;                 ///< error / distance
  size_t losses = 0, reacquired = 0;
  double reacquire_median_s = -1;         ///< -1 if no loss
  double following_distance_error_m = 0;  ///< mean |robot-ball distance - target| following
  double within_tolerance =
      0;  ///< following & visible frames within both tolerances (robot centre)
  double longest_following_without_ball_s = 0;  ///< following while no ball is visible
};

/// Scores one run. Samples may arrive in any order; they are joined by frame seq.
ScenarioMetrics score(const std::string& scenario, const std::vector<TruthSample>& truth,
                      const std::vector<DetectionSample>& detections,
                      const std::vector<TrackSample>& tracks, const MetricsParams& params);

/// One time the track lost the ball (the paper's predictive search): the track went SEARCHING,
/// the robot turned to a side, and the track followed again, or not before the run ended.
struct LeaveEvent {
  uint64_t seq = 0;  ///< frame whose track first said SEARCHING
  double t_s = 0;    ///< its simulated time, s
  /// Ground truth: the side of the left camera's view (x right of the optical axis) the ball was
  /// on at the last frame it was visible, at or before the leave: the side it left by.
  Side ball_side = Side::kUnknown;
  /// The way the robot turned while searching (ground-truth yaw, net turn from search_settle_s
  /// after the leave to the end of the search); kUnknown = it did not turn.
  Side searched = Side::kUnknown;
  double search_end_t_s = 0;   ///< last SEARCHING frame (the run's last frame if never back), s
  bool reacquired = false;     ///< the track went back to FOLLOWING
  double reacquired_t_s = -1;  ///< time of that first FOLLOWING frame, s (-1 = never)
  double reacquire_s = -1;     ///< reacquired_t_s - t_s (-1 = never)
  /// Searched toward the side the ball left by.
  bool searched_ball_side() const { return searched != Side::kUnknown && searched == ball_side; }
};

struct LeaveEventParams {
  /// The search's turn is judged from this long after the leave on: the base first brakes the
  /// turn it had while following (a search shorter than this is judged on its whole turn).
  double search_settle_s = 0.5;
  double min_turn_rad = 0.05;  ///< a smaller net turn shows no search direction
};

/// Leave events of one run: every change of the track state into SEARCHING, judged against the
/// ground truth. Samples may arrive in any order; they are joined by frame seq, and a frame
/// without a track keeps the state of the last track before it.
std::vector<LeaveEvent> leave_events(const std::vector<TruthSample>& truth,
                                     const std::vector<TrackSample>& tracks,
                                     const LeaveEventParams& params = {});

/// "left", "right" or "-" (unknown).
const char* side_name(Side side);

/// Horizontal distance sqrt(x^2 + z^2) and bearing atan2(x, z) of a camera-frame point.
double horizontal_distance_m(const double p[3]);
double bearing_rad(const double p[3]);

/// Distance on the floor from the robot's centre to the ball's centre (world truth), m: what
/// the controller's target_distance_m refers to.
double robot_ball_distance_m(const TruthSample& t);
/// Angle of the ball's centre from the robot's heading (world truth), rad in (-pi, pi],
/// positive = ball to the RIGHT (the sign of bearing_rad).
double robot_ball_bearing_rad(const TruthSample& t);

}  // namespace stereoball::demo
