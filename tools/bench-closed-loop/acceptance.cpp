#include "acceptance.hpp"

#include <cmath>

namespace stereoball::bench_closed_loop {
namespace {

bool visible(const Sample& s) {
  return s.truth.ball_present && s.truth.visible;
}

// Following the real ball: an accepted track position close to the true ball centre.
bool following_the_ball(const Sample& s, double on_ball_m) {
  if (!visible(s) || s.track.state != demo::TrackState::kFollowing || !s.track.accepted) {
    return false;
  }
  const double dx = s.track.position_m[0] - s.truth.ball_cam_m[0];
  const double dy = s.track.position_m[1] - s.truth.ball_cam_m[1];
  const double dz = s.track.position_m[2] - s.truth.ball_cam_m[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz) <= on_ball_m;
}

// Index of the first visible frame at or after i (samples.size() if none).
std::size_t next_visible(const std::vector<Sample>& samples, std::size_t i) {
  while (i < samples.size() && !visible(samples[i])) ++i;
  return i;
}

// Follows one departure at index i (first frame out of view) to its outcome.
LeaveEvent follow_departure(const std::vector<Sample>& samples, std::size_t i,
                            const AcceptanceParams& p) {
  LeaveEvent e;
  e.t_s = samples[i].truth.t_s;
  e.side = demo::robot_ball_bearing_rad(samples[i - 1].truth) > 0.0 ? Side::kRight : Side::kLeft;
  for (std::size_t k = i; k < samples.size(); ++k) {
    const Sample& s = samples[k];
    if (s.truth.t_s - e.t_s > p.reacquire_limit_s) break;
    if (e.turned == Side::kNone && s.searching && std::abs(s.angular_radps) >= p.search_turn_radps)
      e.turned = s.angular_radps > 0.0 ? Side::kLeft : Side::kRight;
    if (following_the_ball(s, p.on_ball_m)) {
      e.reacquired = true;
      e.reacquire_s = s.truth.t_s - e.t_s;
      break;
    }
  }
  e.cut_off = !e.reacquired && samples.back().truth.t_s - e.t_s < p.reacquire_limit_s;
  // Coming back into view before any search is not a wrong turn.
  e.right_way = e.turned == e.side || (e.turned == Side::kNone && e.reacquired);
  return e;
}

}  // namespace

const char* to_string(Side side) {
  return side == Side::kLeft ? "left" : side == Side::kRight ? "right" : "none";
}

KeepFigures keep_figures(const std::vector<Sample>& samples, const AcceptanceParams& p) {
  KeepFigures k;
  const double dt = p.frame_period_s;
  double since_s = -1.0;  // start of the current stretch of visible, slow-enough ball
  for (const Sample& s : samples) {
    const bool seen = visible(s);
    const bool slow = s.ball_speed_mps <= p.max_ball_speed_mps;
    if (seen) k.visible_s += dt;
    if (seen && !slow) k.fast_s += dt;
    if (!seen || !slow) {
      since_s = -1.0;
      continue;
    }
    if (since_s < 0.0) since_s = s.truth.t_s;
    if (s.truth.t_s - since_s < p.settle_s - 1e-9) continue;  // frame times are rounded
    ++k.reachable_frames;
    k.reachable_s += dt;
    const double distance_error = demo::robot_ball_distance_m(s.truth) - p.target_distance_m;
    const double bearing = std::abs(demo::robot_ball_bearing_rad(s.truth));
    const bool distance_ok = std::abs(distance_error) <= p.distance_tolerance_m;
    const bool bearing_ok = bearing <= p.bearing_tolerance_rad;
    k.distance_error_sum_m += distance_error;
    k.abs_bearing_sum_rad += bearing;
    if (distance_ok) k.distance_ok_s += dt;
    if (bearing_ok) k.bearing_ok_s += dt;
    if (distance_ok && bearing_ok) k.kept_s += dt;
    if (s.track.state == demo::TrackState::kFollowing) k.following_s += dt;
  }
  return k;
}

std::vector<LeaveEvent> leave_events(const std::vector<Sample>& samples,
                                     const AcceptanceParams& p) {
  std::vector<LeaveEvent> out;
  std::size_t i = 1;
  while (i < samples.size()) {
    if (!(visible(samples[i - 1]) && !visible(samples[i]) && samples[i].truth.ball_present)) {
      ++i;
      continue;
    }
    const std::size_t back = next_visible(samples, i);
    const double gap_end_s = back < samples.size() ? samples[back].truth.t_s
                                                   : samples.back().truth.t_s + p.frame_period_s;
    // Short dropouts (edge of the image, a thin occluder) are not "leaving the view".
    if (gap_end_s - samples[i].truth.t_s >= p.min_gap_s)
      out.push_back(follow_departure(samples, i, p));
    i = back + 1;
  }
  return out;
}

std::size_t judged_leaves(const std::vector<LeaveEvent>& events) {
  std::size_t n = 0;
  for (const auto& e : events) n += e.cut_off ? 0 : 1;
  return n;
}

bool leave_run_ok(const std::vector<LeaveEvent>& events) {
  for (const auto& e : events)
    if (!e.cut_off && !(e.right_way && e.reacquired)) return false;
  return true;
}

RunAcceptance judge_run(const std::string& scenario, const std::vector<Sample>& samples,
                        const AcceptanceParams& p) {
  RunAcceptance r;
  std::vector<demo::TruthSample> truth;
  std::vector<demo::DetectionSample> detections;
  std::vector<demo::TrackSample> tracks;
  for (const Sample& s : samples) {
    r.ball_present = r.ball_present || s.truth.ball_present;
    truth.push_back(s.truth);
    detections.push_back(s.detection);
    tracks.push_back(s.track);
  }
  r.keep = keep_figures(samples, p);
  r.leaves = leave_events(samples, p);
  demo::MetricsParams mp;
  mp.target_distance_m = p.target_distance_m;
  mp.distance_tolerance_m = p.distance_tolerance_m;
  mp.bearing_tolerance_rad = p.bearing_tolerance_rad;
  mp.false_error_m = p.on_ball_m;
  mp.min_gap_s = p.min_gap_s;
  r.metrics = demo::score(scenario, truth, detections, tracks, mp);
  // With no ball at all, following anything is following clutter.
  r.longest_following_no_ball_s = r.ball_present ? 0.0 : r.metrics.longest_following_without_ball_s;
  return r;
}

}  // namespace stereoball::bench_closed_loop
