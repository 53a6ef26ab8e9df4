#include "metrics.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace stereoball::demo {
namespace {

double distance3(const double a[3], const double b[3]) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5))];
}

}  // namespace

double horizontal_distance_m(const double p[3]) {
  return std::hypot(p[0], p[2]);
}
double bearing_rad(const double p[3]) {
  return std::atan2(p[0], p[2]);
}

double robot_ball_distance_m(const TruthSample& t) {
  return std::hypot(t.ball_world_m[0] - t.robot_world_m[0], t.ball_world_m[1] - t.robot_world_m[1]);
}

double robot_ball_bearing_rad(const TruthSample& t) {
  const double heading =
      std::atan2(t.ball_world_m[1] - t.robot_world_m[1], t.ball_world_m[0] - t.robot_world_m[0]);
  // World yaw is counter-clockwise (left) positive; the bearing is right positive.
  return -std::remainder(heading - t.robot_yaw_rad, 2.0 * M_PI);
}

const char* side_name(Side side) {
  return side == Side::kLeft ? "left" : side == Side::kRight ? "right" : "-";
}

namespace {

// Net counter-clockwise turn of the robot from frame a to frame b (indices into truth, a <= b),
// rad, unwrapped frame by frame.
double net_turn_rad(const std::vector<TruthSample>& truth, size_t a, size_t b) {
  double turn = 0;
  for (size_t k = a + 1; k <= b; ++k)
    turn += std::remainder(truth[k].robot_yaw_rad - truth[k - 1].robot_yaw_rad, 2.0 * M_PI);
  return turn;
}

}  // namespace

std::vector<LeaveEvent> leave_events(const std::vector<TruthSample>& truth_in,
                                     const std::vector<TrackSample>& tracks,
                                     const LeaveEventParams& params) {
  std::vector<TruthSample> truth = truth_in;
  std::sort(truth.begin(), truth.end(), [](auto& a, auto& b) { return a.seq < b.seq; });
  std::map<uint64_t, TrackState> state_by_seq;
  for (const auto& t : tracks) state_by_seq[t.seq] = t.state;
  // The track state in force at every truth frame.
  std::vector<TrackState> state(truth.size(), TrackState::kIdle);
  TrackState current = TrackState::kIdle;
  for (size_t i = 0; i < truth.size(); ++i) {
    if (auto it = state_by_seq.find(truth[i].seq); it != state_by_seq.end()) current = it->second;
    state[i] = current;
  }
  std::vector<LeaveEvent> out;
  size_t i = 0;
  while (i < truth.size()) {
    const bool starts =
        state[i] == TrackState::kSearching && (i == 0 || state[i - 1] != TrackState::kSearching);
    if (!starts) {
      ++i;
      continue;
    }
    LeaveEvent e;
    e.seq = truth[i].seq;
    e.t_s = truth[i].t_s;
    for (size_t k = i + 1; k-- > 0;) {
      if (truth[k].ball_present && truth[k].visible) {
        e.ball_side = truth[k].ball_cam_m[0] > 0 ? Side::kRight : Side::kLeft;
        break;
      }
    }
    size_t end = i;  // last searching frame
    while (end + 1 < truth.size() && state[end + 1] == TrackState::kSearching) ++end;
    e.search_end_t_s = truth[end].t_s;
    if (end + 1 < truth.size() && state[end + 1] == TrackState::kFollowing) {
      e.reacquired = true;
      e.reacquired_t_s = truth[end + 1].t_s;
      e.reacquire_s = e.reacquired_t_s - e.t_s;
    }
    // The turn up to the frame that ends the search (its yaw is where the search brought it).
    const size_t turn_end = std::min(end + 1, truth.size() - 1);
    size_t turn_start = i;
    while (turn_start < turn_end && truth[turn_start].t_s - e.t_s < params.search_settle_s)
      ++turn_start;
    if (turn_start >= turn_end) turn_start = i;  // a short search: its whole turn
    const double turn = net_turn_rad(truth, turn_start, turn_end);
    // Counter-clockwise (positive yaw) is a turn to the left.
    if (std::abs(turn) >= params.min_turn_rad) e.searched = turn > 0 ? Side::kLeft : Side::kRight;
    out.push_back(e);
    i = end + 1;
  }
  return out;
}

ScenarioMetrics score(const std::string& scenario, const std::vector<TruthSample>& truth_in,
                      const std::vector<DetectionSample>& detections,
                      const std::vector<TrackSample>& tracks, const MetricsParams& params) {
  std::vector<TruthSample> truth = truth_in;
  std::sort(truth.begin(), truth.end(), [](auto& a, auto& b) { return a.seq < b.seq; });
  std::map<uint64_t, const DetectionSample*> det_by_seq;
  for (const auto& d : detections) det_by_seq[d.seq] = &d;
  std::map<uint64_t, const TrackSample*> track_by_seq;
  for (const auto& t : tracks) track_by_seq[t.seq] = &t;

  ScenarioMetrics m;
  m.scenario = scenario;
  m.frames = truth.size();
  size_t found_visible = 0, false_accepted = 0, accepted_visible = 0, follow_frames = 0, within = 0;
  std::vector<double> errors, rel_errors;
  double follow_err_sum = 0;
  TrackState state = TrackState::kIdle;
  bool was_visible = false;
  double invisible_since = -1, visible_again_at = -1, following_blind_since = -1;
  std::vector<double> reacquire_s;

  for (const auto& gt : truth) {
    const auto* det = det_by_seq.count(gt.seq) ? det_by_seq[gt.seq] : nullptr;
    const auto* trk = track_by_seq.count(gt.seq) ? track_by_seq[gt.seq] : nullptr;
    if (trk) state = trk->state;
    if (gt.visible) ++m.visible_frames;
    if (det && det->found) {
      // Judged in 3D whenever there is a ball: a detection of it entering or leaving the view
      // (its centre out of one image) is not a false one.
      const bool is_ball =
          gt.ball_present && distance3(det->position_m, gt.ball_cam_m) <= params.false_error_m;
      if (is_ball && gt.visible)
        ++found_visible;
      else if (!is_ball)
        ++m.false_detections;
      if (!is_ball && trk && trk->accepted) ++false_accepted;
    }
    if (trk && trk->accepted) {
      ++m.accepted_frames;
      if (gt.visible) {
        ++accepted_visible;
        const double e = distance3(trk->position_m, gt.ball_cam_m);
        errors.push_back(e);
        rel_errors.push_back(e / std::max(0.1, horizontal_distance_m(gt.ball_cam_m)));
      }
    }
    // Losses and reacquisition: a visibility gap longer than min_gap_s, then the time from
    // visibility returning to the first accepted detection.
    if (!gt.visible && was_visible) invisible_since = gt.t_s;
    if (gt.visible && !was_visible && invisible_since >= 0 &&
        gt.t_s - invisible_since >= params.min_gap_s) {
      ++m.losses;
      visible_again_at = gt.t_s;
    }
    if (visible_again_at >= 0 && trk && trk->accepted && gt.visible) {
      reacquire_s.push_back(gt.t_s - visible_again_at);
      ++m.reacquired;
      visible_again_at = -1;
    }
    was_visible = gt.visible;
    if (state == TrackState::kFollowing) {
      if (gt.visible) {
        ++follow_frames;
        // The controller keeps the distance from the robot's centre and points its centreline.
        const double dist_err = std::abs(robot_ball_distance_m(gt) - params.target_distance_m);
        follow_err_sum += dist_err;
        if (dist_err <= params.distance_tolerance_m &&
            std::abs(robot_ball_bearing_rad(gt)) <= params.bearing_tolerance_rad) {
          ++within;
        }
      }
      if (!gt.ball_present || !gt.visible) {
        if (following_blind_since < 0) following_blind_since = gt.t_s;
        m.longest_following_without_ball_s =
            std::max(m.longest_following_without_ball_s, gt.t_s - following_blind_since);
      } else {
        following_blind_since = -1;
      }
    } else {
      following_blind_since = -1;
    }
  }
  m.detection_rate = m.visible_frames ? static_cast<double>(found_visible) / m.visible_frames : 0;
  m.false_accept_rate =
      m.false_detections ? static_cast<double>(false_accepted) / m.false_detections : 0;
  m.accept_rate_visible =
      m.visible_frames ? static_cast<double>(accepted_visible) / m.visible_frames : 0;
  m.error_median_m = quantile(errors, 0.5);
  m.error_p95_m = quantile(errors, 0.95);
  m.error_median_rel = quantile(rel_errors, 0.5);
  m.reacquire_median_s = reacquire_s.empty() ? -1 : quantile(reacquire_s, 0.5);
  m.following_distance_error_m = follow_frames ? follow_err_sum / follow_frames : 0;
  m.within_tolerance = follow_frames ? static_cast<double>(within) / follow_frames : 0;
  return m;
}

}  // namespace stereoball::demo
